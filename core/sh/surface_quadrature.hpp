#pragma once
// Samples for an SH fit against the SURFACE rather than its vertices (issue 37 item 3): the fit's objective
//   Σ_i w_i |Y(u_i) C − X_i|²  ≈  ∫_M |Y(u(p)) C − p|² dA(p) / A
// evaluated by quadrature over the input's triangles, where u(p) is the map interpolated linearly on the chord
// triangle and projected to the sphere (u(p) = Σ b_k u_k / ‖Σ b_k u_k‖ for barycentric b). At the vertices alone an
// Lmax-10 fit (121 coefficients per coordinate) is under-determined on a coarse mesh (252 vertices) and its ξ depends
// on the triangulation (measured: log ξ apart by up to 10 between 252 and 4,002 vertices of identical geometry);
// over the surface the objective is the same integral at every resolution that resolves the shape.
// Rule: each face is split into m² sub-triangles, m the smallest integer for which every sub-triangle's chord edges
// on the sphere are at most kMaxSampleSpacing / (Lmax + 1) radians (so the degree-Lmax basis varies little across a
// sub-triangle; m ≤ kMaxFaceSplits), and each sub-triangle gets the 3-point rule of degree 2 (barycentric
// (2/3, 1/6, 1/6) and its permutations, weights 1/3 of its area). Weights are input-surface areas (faces of zero
// area carry none), summing to the surface area.

#include <Eigen/Core>

#include "core/mesh/mesh.hpp"

namespace wish {

inline constexpr double kMaxSampleSpacing = 0.5;  // radians × (Lmax + 1): a sixth of the shortest wavelength 2π/L
inline constexpr int kMaxFaceSplits = 24;

struct SurfaceSamples {
  Eigen::MatrixX3d sphere_points;  // n × 3 unit vectors
  Eigen::MatrixX3d targets;        // n × 3 surface points (input units)
  Eigen::VectorXd weights;         // n input-area weights (sum: the surface area)
};

// Requires sphere.rows() == input.vertex_count() (unit rows, a bijective map).
SurfaceSamples surface_quadrature(const Mesh& input, const Eigen::MatrixX3d& sphere, int lmax);

}  // namespace wish
