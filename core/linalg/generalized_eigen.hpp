#pragma once
// The smallest eigenpairs of a sparse symmetric generalised problem  L u = λ M u  with L symmetric positive
// SEMIdefinite (a cotan Laplacian: L·1 = 0) and M diagonal positive (a lumped mass), as ShapeDNA needs
// (core/classify/laplace_spectrum.hpp).
//
// Method: shift-invert block Krylov with Rayleigh-Ritz and restarts. With σ = -shift < 0, A = L + shift·M is
// positive definite (factored once by CHOLMOD; a factorisation failure is reported, never hidden), and
//   B = M^(1/2) A^(-1) M^(1/2)
// is symmetric with eigenvalues θ = 1 / (λ + shift): the smallest λ are B's largest θ, well separated. Each cycle
// builds an orthonormal basis of span{X, B X, ..., B^(s-1) X} (X: the block, the previous cycle's Ritz vectors),
// solves the small dense problem Qᵀ B Q, and keeps the leading Ritz vectors. A block (more columns than wanted
// eigenvalues) rather than single-vector Lanczos so that multiple eigenvalues (the sphere's l(l+1), 2l+1 times) are
// all found: a single Krylov vector sees one direction of each eigenspace only.
// Convergence: every wanted pair's residual |L u - λ M u|_(M^-1) <= tolerance · (λ + shift) |u|_M; the result
// carries the residuals and a status, non-convergence is a status (not an exception), as Eigen does.

#include <string>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace wish::linalg {

struct GeneralizedEigenOptions {
  int count = 10;              // eigenpairs wanted (the smallest), >= 1
  double shift = 1.0;          // A = L + shift·M (> 0; in the units of λ)
  int extra_columns = 8;       // block size = count + extra_columns (guards multiplicity up to that)
  int krylov_blocks = 4;       // s: blocks per Krylov basis (basis size s·block)
  int max_cycles = 60;         // restarts before giving up (status NotConverged)
  double tolerance = 1e-8;     // relative residual, see above
  unsigned seed = 1;           // the random start block (deterministic)
};

enum class EigenStatus { Converged, NotConverged, FactorizationFailed, InvalidInput };
const char* to_string(EigenStatus status);

struct GeneralizedEigenResult {
  EigenStatus status = EigenStatus::InvalidInput;
  Eigen::VectorXd values;       // ascending, `count` of them (fewer only when the problem is smaller)
  Eigen::MatrixXd vectors;      // n x count, M-orthonormal (uᵀ M u = 1)
  Eigen::VectorXd residuals;    // relative residual of each pair (see above)
  int cycles = 0;               // restart cycles run
  std::string message;          // why it failed, empty when converged
};

// L: n x n symmetric (both triangles stored), PSD; mass: n positive entries (diagonal of M).
GeneralizedEigenResult smallest_generalized_eigenpairs(const Eigen::SparseMatrix<double>& L, const Eigen::VectorXd& mass,
                                                        const GeneralizedEigenOptions& options = {});

}  // namespace wish::linalg
