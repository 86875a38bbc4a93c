// linalg::symmetric_eigen (core/linalg/symmetric_eigen.hpp): the spectrum of a matrix built from a known one.
#include <algorithm>
#include <cstdlib>

#include <Eigen/QR>
#include <gtest/gtest.h>

#include "core/linalg/symmetric_eigen.hpp"

namespace wish::linalg {
namespace {

// Q diag(values) Qᵀ with Q a random orthogonal matrix (the Q of a QR of a seeded random matrix).
Eigen::MatrixXd with_spectrum(const Eigen::VectorXd& values, unsigned seed) {
  std::srand(seed);
  const Eigen::Index n = values.size();
  const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(Eigen::MatrixXd::Random(n, n)).householderQ();
  return q * values.asDiagonal() * q.transpose();
}

TEST(SymmetricEigen, RecoversAKnownSpectrumInAscendingOrder) {
  Eigen::VectorXd values(6);
  values << 3.0, -2.0, 0.5, 7.0, 1e-3, 0.5;  // a repeated value and a negative one
  const Eigen::MatrixXd a = with_spectrum(values, 7);
  const SymmetricEigen eig = symmetric_eigen(a);
  ASSERT_TRUE(eig.converged);
  Eigen::VectorXd sorted = values;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_LT((eig.values - sorted).cwiseAbs().maxCoeff(), 1e-12);
  // Orthonormal eigenvectors that diagonalise A: A V = V Λ and VᵀV = I.
  EXPECT_LT((a * eig.vectors - eig.vectors * eig.values.asDiagonal()).norm(), 1e-12);
  EXPECT_LT((eig.vectors.transpose() * eig.vectors - Eigen::MatrixXd::Identity(6, 6)).norm(), 1e-12);
}

TEST(SymmetricEigen, ReadsTheLowerTriangleOnly) {
  Eigen::VectorXd values(4);
  values << 1.0, 2.0, 4.0, 8.0;
  const Eigen::MatrixXd a = with_spectrum(values, 11);
  Eigen::MatrixXd lower_only = a;
  lower_only.triangularView<Eigen::StrictlyUpper>().setConstant(99.0);  // garbage the solver must not read
  const SymmetricEigen eig = symmetric_eigen(lower_only);
  ASSERT_TRUE(eig.converged);
  EXPECT_LT((eig.values - values).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace wish::linalg
