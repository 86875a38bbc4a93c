#pragma once
// The quaternionic Dirac system of one spin transformation (CPS11 §5, CPS13 §3; spherical-map.md §4).
//
// For a per-vertex curvature change ρ (real, units 1/length) the spin transformation is the λ (per-vertex
// quaternion) minimising Σ_f A_f |(Dλ)_f − (ρλ)_f|² with ‖λ‖ = 1, where
//   (Dλ)_f = −(1/(2A_f)) Σ_k e_k λ_{i_k}   (e_k: the CCW edge opposite corner k, as an imaginary quaternion)
//   (ρλ)_f = (1/3) Σ_k ρ_{i_k} λ_{i_k}.
// Expanding gives the quaternion-Hermitian V×V matrix 𝔼, face by face for every ordered corner pair (k, l):
//   𝔼[i_k, i_l] += −(1/(4A_f)) e_k e_l + (1/6)(ρ_{i_k} e_l − ρ_{i_l} e_k) + (A_f/9) ρ_{i_k} ρ_{i_l}.
// Stored as the real symmetric positive semidefinite 4V×4V matrix whose (i, j) block is left_block(𝔼[i, j]);
// unknowns (w, x, y, z) of λ_i are rows 4i..4i+3. With ρ ≡ 0 the constant quaternion fields are its kernel.
// 𝔼 is right-quaternion-linear, so every eigenvalue has multiplicity 4 (λ ↦ λq only rotates/scales the result).

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "core/geometry/vertex_pattern.hpp"

namespace wish::spherical {

// Fixed 4V×4V pattern built from the V×V vertex pattern: entry (4i+r, 4j+c) of the expanded matrix lives at
// value index column_start[4j+c] + 4·(p − outer[j]) + r, with p the index of (i, j) in the vertex pattern.
struct DiracPattern {
  Eigen::SparseMatrix<double> matrix;  // 4V×4V, full symmetric storage, values overwritten by assemble
  std::vector<int> block_base;         // per vertex-pattern entry p = (i, j): value index of block element (0, 0)
  std::vector<int> block_stride;       // per vertex-pattern entry: distance between consecutive block columns
};

DiracPattern build_dirac_pattern(const geometry::VertexPattern& vertex_pattern);

// Assembles 𝔼(ρ) for the current positions into pattern.matrix. `areas` = face areas. Returns mean(diag 𝔼).
double assemble_dirac(const geometry::VertexPattern& vertex_pattern, DiracPattern& pattern,
                      const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces, const Eigen::VectorXd& areas,
                      const Eigen::VectorXd& rho);

// Convenience for tests: pattern + assembly in one call.
Eigen::SparseMatrix<double> dirac_matrix(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                         const Eigen::VectorXd& rho);

}  // namespace wish::spherical
