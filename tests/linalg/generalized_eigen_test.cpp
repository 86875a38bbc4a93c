// Smallest eigenpairs of L u = λ M u (core/linalg/generalized_eigen.hpp) against closed forms.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "core/linalg/generalized_eigen.hpp"

namespace wish::linalg {
namespace {

// Laplacian of the path graph on n vertices (free ends), PSD: eigenvalues 2 - 2 cos(k π / n), k = 0..n-1, simple.
// `copies` disjoint paths: every eigenvalue `copies` times.
Eigen::SparseMatrix<double> path_laplacian(int n, int copies = 1) {
  std::vector<Eigen::Triplet<double>> t;
  for (int c = 0; c < copies; ++c)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = c * n + i, b = a + 1;
      t.emplace_back(a, a, 1.0);
      t.emplace_back(b, b, 1.0);
      t.emplace_back(a, b, -1.0);
      t.emplace_back(b, a, -1.0);
    }
  Eigen::SparseMatrix<double> L(n * copies, n * copies);
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

double path_eigenvalue(int n, int k) { return 2 - 2 * std::cos(k * std::numbers::pi / n); }

TEST(GeneralizedEigen, PathGraphWithScaledMass) {
  const int n = 600;
  const double m = 0.25;  // M = m I: λ = (2 - 2 cos(k π / n)) / m
  GeneralizedEigenOptions o;
  o.count = 12;
  o.shift = 1e-3;
  const auto r = smallest_generalized_eigenpairs(path_laplacian(n), Eigen::VectorXd::Constant(n, m), o);
  ASSERT_EQ(r.status, EigenStatus::Converged) << r.message;
  ASSERT_EQ(r.values.size(), 12);
  EXPECT_NEAR(r.values(0), 0.0, 1e-10);
  for (int k = 1; k < 12; ++k) EXPECT_NEAR(r.values(k), path_eigenvalue(n, k) / m, 1e-9 * path_eigenvalue(n, k) / m) << k;
  EXPECT_LE(r.residuals.maxCoeff(), o.tolerance);
  // M-orthonormal vectors.
  const Eigen::MatrixXd gram = r.vectors.transpose() * (m * r.vectors);
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(12, 12)).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(GeneralizedEigen, FindsEveryCopyOfAMultipleEigenvalue) {
  // Four disjoint paths: each eigenvalue four times, which a single-vector Krylov method would see once.
  const int n = 300, copies = 4;
  GeneralizedEigenOptions o;
  o.count = 12;
  o.shift = 1e-2;
  const auto r = smallest_generalized_eigenpairs(path_laplacian(n, copies), Eigen::VectorXd::Ones(n * copies), o);
  ASSERT_EQ(r.status, EigenStatus::Converged) << r.message;
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(r.values(i), path_eigenvalue(n, i / copies), 1e-9) << i;
}

TEST(GeneralizedEigen, SmallProblemsAndFailuresAreReported) {
  GeneralizedEigenOptions o;
  o.count = 3;
  const auto small = smallest_generalized_eigenpairs(path_laplacian(10), Eigen::VectorXd::Ones(10), o);
  ASSERT_EQ(small.status, EigenStatus::Converged);
  EXPECT_NEAR(small.values(2), path_eigenvalue(10, 2), 1e-12);
  EXPECT_EQ(smallest_generalized_eigenpairs(path_laplacian(10), Eigen::VectorXd::Zero(10), o).status, EigenStatus::InvalidInput);
  EXPECT_EQ(smallest_generalized_eigenpairs(path_laplacian(10), Eigen::VectorXd::Ones(9), o).status, EigenStatus::InvalidInput);
  // An indefinite "Laplacian" (negated): L + shift M is not positive definite, and that is said, not hidden.
  const Eigen::SparseMatrix<double> negative = -path_laplacian(500);
  const auto r = smallest_generalized_eigenpairs(negative, Eigen::VectorXd::Ones(500), o);
  EXPECT_EQ(r.status, EigenStatus::FactorizationFailed);
  EXPECT_FALSE(r.message.empty());
}

}  // namespace
}  // namespace wish::linalg
