#pragma once
// Cotangent Laplacian, POSITIVE SEMIDEFINITE convention (docs/design/spherical-map.md §1):
//   w_ij = ½ (cot α_ij + cot β_ij) over the two corners opposite edge ij,  L_ij = −w_ij (i ≠ j),  L_ii = Σ_j w_ij,
// so L·1 = 0 and xᵀLx = ½ Σ_ij w_ij |x_i − x_j|² ≥ 0 (Dirichlet energy ×2). libigl's cotmatrix is −L.
// Units: dimensionless (cotangents), so (Lx)_i ≈ 2 M_i H_i N_i has units of length.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "core/geometry/vertex_pattern.hpp"

namespace wish::geometry {

// L from positions, on the fixed pattern (values overwritten). `cot` = corner_cotangents(vertices, faces).
void assemble_cotan_laplacian(const VertexPattern& pattern, const Eigen::MatrixX3i& faces, const Eigen::MatrixX3d& cot,
                              Eigen::SparseMatrix<double>& laplacian);

// Convenience: builds the pattern and assembles L.
Eigen::SparseMatrix<double> cotan_laplacian(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces);

}  // namespace wish::geometry
