#pragma once
// The two linear-algebra halves of one spin transformation (CPS11 §5; docs/design/spherical-map.md §4–5):
//  1. λ = smallest eigenvector of the Dirac matrix 𝔼(ρ) by shifted inverse power iteration, with a residual check;
//  2. new edge vectors ẽ = ∫₀¹ conj(λ(t)) e λ(t) dt, their cot-weighted divergence ω, and the Poisson solve
//     L x̃ = ω (PSD cot Laplacian of the current mesh, one vertex pinned so the factored matrix is definite).

#include <string>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/linalg/sparse_cholesky.hpp"

namespace wish::spherical {

struct EigenSolveOptions {
  double relative_shift = 1e-10;     // ε = relative_shift · mean(diag 𝔼); keeps 𝔼 + εI definite as ρ → 0
  double shift_growth = 100.0;       // on a failed factorisation ε ← ε·shift_growth and refactor ...
  int max_shift_retries = 4;         // ... at most this many times
  int max_iterations = 5;            // inverse iterations (1 is usually enough)
  double residual_tolerance = 1e-8;  // stop iterating when ‖𝔼x − (xᵀ𝔼x)x‖ ≤ this · mean(diag 𝔼)
};

struct EigenSolveReport {
  bool ok = false;           // factorisation succeeded and the result is finite
  double shift = 0;          // ε actually used
  int iterations = 0;
  double residual = 0;       // ‖𝔼x − γx‖ / mean(diag 𝔼), x unit
  double rayleigh = 0;       // γ / mean(diag 𝔼): how far ρ was from integrable
  double factor_seconds = 0, solve_seconds = 0;
  std::string message;
};

// x (unit Euclidean norm) ← smallest eigenvector of `dirac` (real 4V×4V or complex Hermitian 2V×2V form, see
// dirac_operator.hpp; only its lower triangle is read). `solver` keeps its symbolic analysis between calls (the
// pattern of `dirac` must not change).
// Starts from λ ≡ 1 (real part 1 at every vertex).
template <class Scalar>
EigenSolveReport smallest_eigenvector(linalg::SparseCholeskyT<Scalar>& solver, const Eigen::SparseMatrix<Scalar>& dirac,
                                      double mean_diagonal, const EigenSolveOptions& options,
                                      Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& x);

// ω (V×3): ω_i = Σ_j w_ij ẽ_{j→i} with w_ij the cot weights (½ cot per face-edge) and ẽ the transformed edges;
// λ is the 4V eigenvector (w, x, y, z per vertex). With λ ≡ 1, ω = L x.
Eigen::MatrixX3d spin_divergence(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                 const Eigen::MatrixX3d& cot, const Eigen::VectorXd& lambda);

// The same on any edge set with weights (an intrinsic triangulation's: ω_i = Σ_j w_ij ẽ_{j→i} with ẽ from the
// chord x_j − x_i). With λ ≡ 1, ω = L x for the L of those weights — the Poisson step stays exact for any L.
Eigen::MatrixX3d spin_divergence(const Eigen::MatrixX3d& vertices, const std::vector<geometry::IntrinsicEdgeWeight>& edges,
                                 const Eigen::VectorXd& lambda);

// Copies `laplacian` into `pinned` (same pattern) with row and column `pin` replaced by the identity: the factored
// matrix is then definite for a connected mesh, and solving with ω_pin = 0 gives x̃_pin = 0.
void pin_vertex(const Eigen::SparseMatrix<double>& laplacian, int pin, Eigen::SparseMatrix<double>& pinned);

}  // namespace wish::spherical
