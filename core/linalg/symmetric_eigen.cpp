#include "core/linalg/symmetric_eigen.hpp"

#include <Eigen/Eigenvalues>

namespace wish::linalg {

SymmetricEigen symmetric_eigen(const Eigen::MatrixXd& a) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(a);
  SymmetricEigen result;
  result.converged = eig.info() == Eigen::Success;
  if (result.converged) {
    result.values = eig.eigenvalues();
    result.vectors = eig.eigenvectors();
  }
  return result;
}

}  // namespace wish::linalg
