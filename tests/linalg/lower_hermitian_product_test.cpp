#include <complex>

#include <gtest/gtest.h>

#include "core/linalg/lower_hermitian_product.hpp"

namespace wish::linalg {
namespace {

// A random Hermitian matrix with a sparse pattern; returns both triangles.
Eigen::SparseMatrix<std::complex<double>> random_hermitian(int n, double density, unsigned seed) {
  std::srand(seed);
  const Eigen::MatrixXcd dense_random = Eigen::MatrixXcd::Random(n, n);
  Eigen::MatrixXcd h = Eigen::MatrixXcd::Zero(n, n);
  for (int c = 0; c < n; ++c)
    for (int r = c; r < n; ++r)
      if (r == c || std::abs(dense_random(r, c).real()) < density) {
        h(r, c) = r == c ? std::complex<double>(dense_random(r, c).real(), 0) : dense_random(r, c);
        h(c, r) = std::conj(h(r, c));
      }
  return h.sparseView();
}

TEST(LowerHermitianTimes, EqualsTheFullProductAndIgnoresTheUpperTriangle) {
  const Eigen::SparseMatrix<std::complex<double>> full = random_hermitian(40, 0.3, 7);
  const Eigen::VectorXcd x = Eigen::VectorXcd::Random(40);
  const Eigen::VectorXcd expected = full * x;
  // Lower triangle only, and the full matrix (whose upper triangle must be ignored, not added twice).
  const Eigen::SparseMatrix<std::complex<double>> lower = full.triangularView<Eigen::Lower>();
  EXPECT_LT((lower_hermitian_times(lower, x) - expected).norm(), 1e-13 * expected.norm());
  EXPECT_LT((lower_hermitian_times(full, x) - expected).norm(), 1e-13 * expected.norm());
  // Garbage above the diagonal changes nothing.
  Eigen::SparseMatrix<std::complex<double>> polluted = full;
  for (int c = 0; c < polluted.outerSize(); ++c)
    for (Eigen::SparseMatrix<std::complex<double>>::InnerIterator it(polluted, c); it; ++it)
      if (it.row() < c) it.valueRef() = {123.0, -45.0};
  EXPECT_LT((lower_hermitian_times(polluted, x) - expected).norm(), 1e-13 * expected.norm());
}

TEST(LowerHermitianTimes, RealSymmetric) {
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(25, 25);
  const Eigen::MatrixXd sym = a + a.transpose();
  const Eigen::SparseMatrix<double> lower = Eigen::MatrixXd(sym.triangularView<Eigen::Lower>()).sparseView();
  const Eigen::VectorXd x = Eigen::VectorXd::Random(25);
  EXPECT_LT((lower_hermitian_times(lower, x) - sym * x).norm(), 1e-13 * (sym * x).norm());
}

}  // namespace
}  // namespace wish::linalg
