#pragma once
// Robust cotan Laplacian of a triangle mesh from its EDGE LENGTHS, keeping the user's vertices and connectivity
// (docs/design/real-meshes.md "Robust operators"):
//  1. Intrinsic mollification (Sharp & Crane 2020, "A Laplacian for Nonmanifold Triangle Meshes", §4.5): one
//     ε ≥ 0 is added to every edge length so that every triangle satisfies the triangle inequality with margin
//     δ·h̄ (h̄ = mean edge length):  ε = max over faces and corners of max(0, δ·h̄ − (l_ij + l_jk − l_ki)).
//     Zero-area faces (a vertex duplicated at its twin's position, collinear corners) become thin but valid
//     triangles; nothing else moves by more than ε.
//  2. Intrinsic Delaunay triangulation (Bobenko & Springborn 2007; Fisher et al. 2007): edges whose two opposite
//     angles sum to more than π (cot α + cot β < 0) are flipped intrinsically — the new length is the diagonal of
//     the two triangles laid out flat — until every edge is Delaunay. The triangulation (a Δ-complex: loops and
//     multi-edges allowed) has the same vertex set and the same metric, and its cotan weights are all ≥ 0, so
//     L is an M-matrix (maximum principle, Tutte-style embeddings). Per-vertex quantities need no transfer.
// Conventions as cotan_laplacian.hpp: L is POSITIVE SEMIDEFINITE, w_ij = ½ Σ cot of the corners opposite ij,
// L_ij = −w_ij, L_ii = Σ_j w_ij. The lumped mass is M_i = Σ_{f∋i} A_f / 3 over the intrinsic faces (same total
// area as the mollified input triangles).

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace wish::geometry {

enum class LaplacianKind {
  Extrinsic,          // cotans of the mesh's own triangles from positions (docs/design/spherical-map.md §1); not robust
  Mollified,          // cotans from mollified lengths on the mesh's own triangles
  IntrinsicDelaunay,  // mollified lengths, then intrinsic Delaunay flips (the default)
};
const char* to_string(LaplacianKind kind);
LaplacianKind laplacian_kind_from_name(const char* name);  // throws InvalidInputError on an unknown name

struct IntrinsicOptions {
  LaplacianKind kind = LaplacianKind::IntrinsicDelaunay;
  double mollify_delta = 1e-5;  // δ: triangle-inequality margin relative to the mean edge length
  // Flip budget per edge (the queue stops after max_flips_per_edge·E flips; Delaunay needs a small multiple of V).
  int max_flips_per_edge = 20;
  bool operator==(const IntrinsicOptions&) const = default;
};

// What was done to obtain the operator (reported with the map).
struct IntrinsicStats {
  LaplacianKind kind = LaplacianKind::IntrinsicDelaunay;
  double epsilon = 0;                 // length added to every edge (mesh units); 0 = no face needed it
  double relative_epsilon = 0;        // epsilon / mean edge length
  long zero_area_faces = 0;           // input faces with (numerically) zero area before mollification
  long mollified_faces = 0;           // input faces whose triangle inequality margin was below δ·h̄
  long negative_weights_before = 0;   // edges of the input triangulation with w_ij < 0 (after mollification)
  long negative_weights_after = 0;    // edges with w_ij < 0 left after the flips (clamped to 0; 0 unless flip cap hit)
  long flips = 0;                     // intrinsic edge flips done
  bool flip_cap_hit = false;
  long edges = 0;
};

struct IntrinsicEdgeWeight {
  int i = 0, j = 0;      // i != j
  double weight = 0;     // w_ij ≥ 0 (IntrinsicDelaunay) summed over parallel intrinsic edges
};

struct IntrinsicOperator {
  Eigen::SparseMatrix<double> laplacian;     // V×V, PSD, both triangles stored, diagonal present
  Eigen::VectorXd mass;                      // V, lumped intrinsic vertex areas
  std::vector<IntrinsicEdgeWeight> edges;    // the off-diagonal weights, one entry per vertex pair
  Eigen::MatrixX3i faces;                    // the (flipped) intrinsic triangulation
  Eigen::VectorXd input_face_areas;          // F of the INPUT faces, from mollified lengths (all > 0)
  Eigen::MatrixX3d input_cotangents;         // F×3 corner cotangents of the input faces, from mollified lengths
  IntrinsicStats stats;
};

IntrinsicOperator intrinsic_operator(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                     const IntrinsicOptions& options = {});

// The halfedge connectivity the operator starts from (halfedge h = 3f + k runs from corner k to corner k + 1 of face
// f; twin[h] runs the other way). It depends on the faces only, so a flow that rebuilds the operator of its moving
// surface every step builds it once (1.6 ms per operator on a 10.8K-vertex nucleus, 2 % of its map). Throws
// WishError not_closed when an edge has no opposite halfedge, InvalidInputError on a negative index.
struct HalfedgeConnectivity {
  std::vector<std::array<int, 3>> corners;  // per face
  std::vector<int> twin;                    // per halfedge
};
HalfedgeConnectivity halfedge_connectivity(const Eigen::MatrixX3i& faces);
// The same operator from connectivity already built for `faces` (the flips work on a copy: `connectivity` serves
// every later call). Throws std::invalid_argument when it has not 3 halfedges per face.
IntrinsicOperator intrinsic_operator(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                     const HalfedgeConnectivity& connectivity, const IntrinsicOptions& options = {});

// Areas of the mesh's own faces from mollified lengths (step 1 only; no flips): every face > 0. For lumped masses
// of a moving surface (cMCF's M_t) where a full operator is not needed.
Eigen::VectorXd mollified_face_areas(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                     double mollify_delta);

// Triangle area from its side lengths (Heron, in Kahan's cancellation-free ordering); 0 for a violated inequality.
double triangle_area_from_lengths(double a, double b, double c);

}  // namespace wish::geometry
