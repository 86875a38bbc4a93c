#pragma once
// The quaternionic Dirac system of one spin transformation (CPS11 §5, CPS13 §3; docs/design/spherical-map.md §4).
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

#include <complex>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "core/geometry/vertex_pattern.hpp"

namespace wish::spherical {

// Two equivalent storages of 𝔼 (docs/design/spherical-map.md §9 "complex 2V×2V Hermitian representation"):
//  * real 4V×4V symmetric PSD: block (i, j) = left_block(𝔼[i, j]), λ_i = (w, x, y, z) in rows 4i..4i+3;
//  * complex 2V×2V Hermitian PSD: writing q = z₁ + j z₂ (z₁ = a + bi, z₂ = c − di) and λ = w₁ + j w₂ with complex
//    scalars acting on the RIGHT (w₁ = w + xi, w₂ = y − zi), left multiplication by q is the complex-linear map
//    [[z₁, −z̄₂], [z₂, z̄₁]] on (w₁, w₂). Half the dimension, ~2× fewer flops in the Cholesky factorisation.
// Both are assembled into a fixed pattern: entry (b·i+r, b·j+c) of the expanded matrix (block size b = 4 or 2)
// lives at value index block_base[p] + c·block_stride[p] + r, p = index of (i, j) in the vertex pattern.
//
// Optionally the matrix is stored symmetrically permuted, P𝔼Pᵀ with vertex order[k] at block position k (the
// fill-reducing, postordered ordering of the factorisation): CHOLMOD then factors it in its natural ordering,
// reading the stored lower triangle as it is, where a given ordering makes it build two permuted transposed copies
// of the matrix on every numeric factorisation (cholmod_factorize.c; 5 % of a nucleus map's CPU samples). Block
// position k of a solution vector is then vertex order[k].
template <class Scalar>
struct DiracPatternT {
  static constexpr int kBlock = std::is_same_v<Scalar, double> ? 4 : 2;
  // Lower storage: only blocks (i, j) with i >= j (block positions, with an order), diagonal blocks whole (their strictly-upper entries are exact but
  // never read: CHOLMOD and lower_hermitian_times() read the lower triangle). Half the memory of both triangles,
  // which matters at 160K vertices (spherical-map issue: < 1 GiB). Values are overwritten by assembly.
  Eigen::SparseMatrix<Scalar> matrix;
  std::vector<int> block_base;    // −1 for a vertex-pattern entry above the (permuted) diagonal (not stored)
  std::vector<int> block_stride;
  std::vector<int> order;         // vertex at each block position; empty: the identity (no permutation)
};
using DiracPattern = DiracPatternT<double>;
using ComplexDiracPattern = DiracPatternT<std::complex<double>>;

// `order`: empty, or a permutation of the vertices (order[k] = vertex at block position k).
template <class Scalar>
DiracPatternT<Scalar> build_dirac_pattern(const geometry::VertexPattern& vertex_pattern,
                                          const std::vector<int>& order = {});

// Assembles 𝔼(ρ) for the current positions into pattern.matrix. `areas` = face areas. Returns mean(diag 𝔼).
template <class Scalar>
double assemble_dirac(const geometry::VertexPattern& vertex_pattern, DiracPatternT<Scalar>& pattern,
                      const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces, const Eigen::VectorXd& areas,
                      const Eigen::VectorXd& rho);

// Convenience for tests: pattern + assembly in one call; these return both triangles.
Eigen::SparseMatrix<double> dirac_matrix(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                         const Eigen::VectorXd& rho);
Eigen::SparseMatrix<std::complex<double>> dirac_matrix_complex(const Eigen::MatrixX3d& vertices,
                                                               const Eigen::MatrixX3i& faces, const Eigen::VectorXd& rho);

// Quaternion field (4V real, (w, x, y, z) per vertex) <-> complex 2V vector (w₁, w₂) per vertex.
// With `order` (a pattern's order): the field of vertex order[k] is block k of v.
Eigen::VectorXd quaternions_from_complex(const Eigen::VectorXcd& v, const std::vector<int>& order = {});
Eigen::VectorXd quaternions_from_permuted(const Eigen::VectorXd& q, const std::vector<int>& order);
Eigen::VectorXcd complex_from_quaternions(const Eigen::VectorXd& q);

}  // namespace wish::spherical
