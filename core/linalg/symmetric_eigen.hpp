#pragma once
// The eigendecomposition of a dense symmetric matrix: Eigen's SelfAdjointEigenSolver (Householder tridiagonalisation,
// then implicit symmetric QR steps), behind a plain function so that the solver is compiled once, here. Each
// translation unit that instantiates SelfAdjointEigenSolver<MatrixXd> spends about 15 CPU s of the compiler on it
// at -O3, and the service's build had it twice: the novelty whitening and the generalised eigensolver's
// Rayleigh-Ritz step (docs/benchmarks.md, "Third pass: the service's glue at -O1, one eigensolver").

#include <Eigen/Core>

namespace wish::linalg {

struct SymmetricEigen {
  bool converged = false;   // false: Eigen's QR iteration did not converge (values and vectors are then unusable)
  Eigen::VectorXd values;   // ascending
  Eigen::MatrixXd vectors;  // column i: the unit eigenvector of values(i)
};

// Reads the lower triangle of `a` only (as Eigen does); callers with a nearly symmetric matrix pass ½(A + Aᵀ).
SymmetricEigen symmetric_eigen(const Eigen::MatrixXd& a);

}  // namespace wish::linalg
