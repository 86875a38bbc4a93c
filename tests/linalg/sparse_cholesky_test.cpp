#include <complex>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/linalg/blas_info.hpp"
#include "core/linalg/sparse_cholesky.hpp"

namespace wish::linalg {
namespace {

class SparseCholeskyBackends : public ::testing::TestWithParam<CholeskyBackend> {};

// Graph Laplacian of an n×n torus grid (PSD, kernel = constants), built here so this test needs only wish_linalg.
Eigen::SparseMatrix<double> grid_laplacian(int n) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [n](int i, int j) { return ((i + n) % n) * n + (j + n) % n; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      t.emplace_back(id(i, j), id(i, j), 4.0);
      for (auto [di, dj] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}})
        t.emplace_back(id(i, j), id(i + di, j + dj), -1.0);
    }
  Eigen::SparseMatrix<double> l(n * n, n * n);
  l.setFromTriplets(t.begin(), t.end());
  return l;
}

TEST_P(SparseCholeskyBackends, SolvesSpdSystemRepeatedlyWithOneAnalysis) {
  const Eigen::SparseMatrix<double> l = grid_laplacian(20);
  const Eigen::VectorXd mass = Eigen::VectorXd::Constant(l.rows(), 0.5);
  CholeskyOptions o;
  o.backend = GetParam();
  SparseCholesky solver(o);
  ASSERT_TRUE(solver.analyze(l));
  for (double delta : {0.1, 1.0, 10.0}) {
    Eigen::SparseMatrix<double> a = l * delta;
    for (Eigen::Index i = 0; i < a.rows(); ++i) a.coeffRef(i, i) += mass[i];
    ASSERT_TRUE(solver.factorize(a)) << solver.message();
    const Eigen::MatrixXd b = Eigen::MatrixXd::Random(a.rows(), 3);
    const Eigen::MatrixXd x = solver.solve(b);
    EXPECT_LT((a * x - b).norm() / b.norm(), 1e-10);
  }
  EXPECT_GT(solver.factor_nonzeros(), 0);
}

TEST_P(SparseCholeskyBackends, ReleasedValuesAreRefactoredFromTheKeptAnalysis) {
  const Eigen::SparseMatrix<double> l = grid_laplacian(30);
  for (CholmodMode mode : {CholmodMode::Supernodal, CholmodMode::Simplicial}) {
    CholeskyOptions o;
    o.backend = GetParam();
    o.cholmod_mode = mode;
    SparseCholesky solver(o);
    ASSERT_TRUE(solver.factorize(l, 0.5)) << solver.message();
    const Eigen::MatrixXd b = Eigen::MatrixXd::Random(l.rows(), 2);
    const Eigen::MatrixXd x1 = solver.solve(b);
    solver.release_values();
    EXPECT_FALSE(solver.factorized());
    EXPECT_THROW(solver.solve(b), std::logic_error);
    EXPECT_TRUE(solver.analyzed());  // the next factorisation of the same pattern needs no new analysis
    ASSERT_TRUE(solver.factorize(l, 2.0)) << solver.message();
    const Eigen::MatrixXd x2 = solver.solve(b);
    Eigen::SparseMatrix<double> shifted = l;
    for (Eigen::Index i = 0; i < l.rows(); ++i) shifted.coeffRef(i, i) += 2.0;
    EXPECT_LT((shifted * x2 - b).norm() / b.norm(), 1e-10);
    EXPECT_GT((x2 - x1).norm(), 1e-3 * x1.norm());  // really the new matrix, not the released values
  }
}

TEST_P(SparseCholeskyBackends, RefusesSingularAndIndefiniteButAcceptsShift) {
  const Eigen::SparseMatrix<double> l = grid_laplacian(12);  // PSD, kernel = constants
  CholeskyOptions o;
  o.backend = GetParam();
  SparseCholesky solver(o);
  Eigen::SparseMatrix<double> neg = -l;
  EXPECT_FALSE(solver.factorize(neg, 1e-3));
  EXPECT_FALSE(solver.message().empty());
  EXPECT_THROW(solver.solve(Eigen::MatrixXd::Ones(l.rows(), 1)), std::logic_error);
  EXPECT_TRUE(solver.factorize(l, 1e-6)) << solver.message();
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(l.rows());
  const Eigen::VectorXd x = solver.solve(ones);
  EXPECT_NEAR(x.mean(), 1e6, 1e-3 * 1e6);  // (L + εI)⁻¹1 = 1/ε
}

TEST_P(SparseCholeskyBackends, ComplexHermitianSolve) {
  const Eigen::SparseMatrix<double> l = grid_laplacian(12);
  const Eigen::Index n = l.rows();
  std::vector<Eigen::Triplet<std::complex<double>>> t;
  for (int j = 0; j < l.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(l, j); it; ++it) {
      const std::complex<double> v(it.value(), it.row() < it.col() ? 0.1 * it.value() : -0.1 * it.value());
      t.emplace_back(it.row(), it.col(), it.row() == it.col() ? std::complex<double>(it.value() + 1.0) : v);
    }
  Eigen::SparseMatrix<std::complex<double>> a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  CholeskyOptions o;
  o.backend = GetParam();
  ComplexSparseCholesky solver(o);
  ASSERT_TRUE(solver.factorize(a)) << solver.message();
  const Eigen::MatrixXcd b = Eigen::MatrixXcd::Random(n, 2);
  EXPECT_LT((a * solver.solve(b) - b).norm() / b.norm(), 1e-10);
}

// The factor kept from one analysis (analyze() called again every step with the same pattern, as a flow does) must
// give the solution a fresh solver gives: to round-off, for new values and a new shift each time.
TEST_P(SparseCholeskyBackends, ReusedAnalysisSolvesAsAFreshFactor) {
  const Eigen::SparseMatrix<double> l = grid_laplacian(24);
  for (CholmodMode mode : {CholmodMode::Supernodal, CholmodMode::Simplicial, CholmodMode::Auto}) {
    CholeskyOptions o;
    o.backend = GetParam();
    o.cholmod_mode = mode;
    SparseCholesky reused(o);
    const Eigen::MatrixXd b = Eigen::MatrixXd::Random(l.rows(), 3);
    for (int step = 0; step < 4; ++step) {
      Eigen::SparseMatrix<double> a = l * (1.0 + step);
      for (Eigen::Index i = 0; i < a.rows(); ++i) a.coeffRef(i, i) += 0.1 + 0.01 * static_cast<double>(i % 7) * step;
      const double shift = 0.05 * step;
      ASSERT_TRUE(reused.analyze(a) && reused.factorize(a, shift)) << reused.message();
      SparseCholesky fresh(o);
      ASSERT_TRUE(fresh.analyze(a) && fresh.factorize(a, shift)) << fresh.message();
      const Eigen::MatrixXd x = reused.solve(b), y = fresh.solve(b);
      EXPECT_LT((x - y).norm(), 1e-12 * y.norm()) << "step " << step;
      if (step % 2 == 1) reused.release_values();  // the flows release between steps: the analysis stays
    }
    EXPECT_EQ(reused.analysis_count(), 1);
  }
}

// A matrix of the same size but another pattern must not be factored on the old analysis (that would be a wrong
// factor, not an error): factorize() sees the new pattern and analyses again.
TEST_P(SparseCholeskyBackends, NewPatternOfTheSameSizeIsAnalysedAgain) {
  const Eigen::SparseMatrix<double> l = grid_laplacian(16);
  const Eigen::Index n = l.rows();
  // The grid plus long-range couplings (i, i + n/2) that the grid's analysis has no room for; still SPD (strictly
  // diagonally dominant).
  Eigen::SparseMatrix<double> coupled = l;
  for (Eigen::Index i = 0; i < n / 2; ++i) {
    coupled.coeffRef(i + n / 2, i) = -0.5;
    coupled.coeffRef(i, i + n / 2) = -0.5;
    coupled.coeffRef(i, i) += 1.0;
    coupled.coeffRef(i + n / 2, i + n / 2) += 1.0;
  }
  coupled.makeCompressed();
  CholeskyOptions o;
  o.backend = GetParam();
  SparseCholesky solver(o);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(n, 1);
  ASSERT_TRUE(solver.factorize(l, 0.5)) << solver.message();
  ASSERT_TRUE(solver.factorize(coupled, 0.5)) << solver.message();
  EXPECT_EQ(solver.analysis_count(), 2);
  Eigen::SparseMatrix<double> shifted = coupled;
  for (Eigen::Index i = 0; i < n; ++i) shifted.coeffRef(i, i) += 0.5;
  EXPECT_LT((shifted * solver.solve(b) - b).norm() / b.norm(), 1e-10);
  ASSERT_TRUE(solver.factorize(l, 0.5)) << solver.message();  // and back
  EXPECT_EQ(solver.analysis_count(), 3);
  shifted = l;
  for (Eigen::Index i = 0; i < n; ++i) shifted.coeffRef(i, i) += 0.5;
  EXPECT_LT((shifted * solver.solve(b) - b).norm() / b.norm(), 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Backends, SparseCholeskyBackends,
                         ::testing::Values(CholeskyBackend::Cholmod, CholeskyBackend::EigenSimplicial),
                         [](const auto& info) { return std::string(info.param == CholeskyBackend::Cholmod ? "Cholmod" : "Eigen"); });

TEST(SparseCholesky, GivenMetisOrderingWorks) {
  const Eigen::SparseMatrix<double> l = grid_laplacian(20);
  CholeskyOptions o;
  o.permutation = metis_ordering(l);
  ASSERT_EQ(o.permutation.size(), static_cast<size_t>(l.rows()));
  SparseCholesky solver(o);
  ASSERT_TRUE(solver.factorize(l, 1e-3)) << solver.message();
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(l.rows(), 1);
  Eigen::SparseMatrix<double> a = l;
  for (Eigen::Index i = 0; i < a.rows(); ++i) a.coeffRef(i, i) += 1e-3;
  EXPECT_LT((a * solver.solve(b) - b).norm() / b.norm(), 1e-9);
  const std::vector<int> e = expand_ordering({2, 0, 1}, 2);
  EXPECT_EQ(e, (std::vector<int>{4, 5, 0, 1, 2, 3}));
}

TEST(BlasInfo, ReportsSomething) {
  const BlasInfo info = blas_info();
  EXPECT_FALSE(info.name.empty());
  if (info.openblas) {
    EXPECT_TRUE(set_blas_threads(1));
    EXPECT_EQ(blas_info().threads, 1);
  }
  EXPECT_FALSE(describe_blas().empty());
}

}  // namespace
}  // namespace wish::linalg
