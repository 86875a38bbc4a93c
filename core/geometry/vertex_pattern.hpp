#pragma once
// The sparsity pattern of every vertex-by-vertex operator of a triangle mesh (cot Laplacian, mass, cMCF system,
// and — expanded to 4×4 blocks — the quaternionic Dirac operator): entry (i, j) exists iff i == j or ij is an edge.
// Built once per mesh; afterwards per-face 3×3 contributions are scattered straight into the value array, so a
// matrix with fixed connectivity is reassembled in O(F) without triplets or sorting (and a sparse Cholesky
// factorisation can keep its symbolic analysis).

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace wish::geometry {

struct VertexPattern {
  // V×V, column-major, full (both triangles) and compressed, diagonal included, row indices sorted; values 0.
  Eigen::SparseMatrix<double> pattern;
  // slot[f][3*k + l] = index into pattern.valuePtr() of entry (faces(f,k), faces(f,l)).
  std::vector<std::array<int, 9>> slot;
  // Index into valuePtr() of diagonal entry (i, i).
  std::vector<int> diagonal;
  long edge_count = 0;  // undirected edges
};

VertexPattern build_vertex_pattern(Eigen::Index vertex_count, const Eigen::MatrixX3i& faces);

}  // namespace wish::geometry
