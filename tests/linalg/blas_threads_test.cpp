// stop_blas_threads (core/common/thread_policy.hpp): OpenBLAS's helper threads are gone afterwards, and the BLAS
// still computes — on one thread, and on two again once asked for (it restarts its threads). Own executable: it
// counts the threads of this process.
#include <filesystem>
#include <vector>

#include <gtest/gtest.h>

#include "core/common/thread_policy.hpp"
#include "core/linalg/blas_info.hpp"
#include "core/linalg/sparse_cholesky.hpp"

namespace wish::linalg {
namespace {

long thread_count() {
  long n = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) ++n;
  return n;
}

// Shifted 5-point Laplacian of an n×n grid (SPD); at n = 150 the supernodal factor's BLAS calls are large enough
// for OpenBLAS to use its threads.
Eigen::SparseMatrix<double> shifted_grid_laplacian(int n) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [n](int i, int j) { return i * n + j; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      t.emplace_back(id(i, j), id(i, j), 4.01);
      if (i + 1 < n) t.emplace_back(id(i + 1, j), id(i, j), -1.0), t.emplace_back(id(i, j), id(i + 1, j), -1.0);
      if (j + 1 < n) t.emplace_back(id(i, j + 1), id(i, j), -1.0), t.emplace_back(id(i, j), id(i, j + 1), -1.0);
    }
  Eigen::SparseMatrix<double> l(n * n, n * n);
  l.setFromTriplets(t.begin(), t.end());
  return l;
}

// ‖A x − b‖ / ‖b‖ of a supernodal solve (the factorisation runs dsyrk/dgemm/dtrsm in OpenBLAS).
double relative_residual(const Eigen::SparseMatrix<double>& a) {
  CholeskyOptions options;
  options.cholmod_mode = CholmodMode::Supernodal;
  SparseCholesky solver(options);
  if (!solver.factorize(a)) return -1;
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), 1.0, 2.0);
  const Eigen::VectorXd x = solver.solve(b);
  return (a * x - b).norm() / b.norm();
}

TEST(BlasThreads, StopJoinsTheHelperThreadsAndTheBlasStillComputes) {
  if (!blas_info().openblas) GTEST_SKIP() << "the BLAS is not OpenBLAS: " << blas_info().name;
  const Eigen::SparseMatrix<double> a = shifted_grid_laplacian(150);
  ASSERT_TRUE(set_blas_thread_count(2));
  const long with_helpers = thread_count();
  ASSERT_GE(with_helpers, 2) << "OpenBLAS started no helper thread for 2 threads";
  const double r2 = relative_residual(a);
  EXPECT_GE(r2, 0);
  EXPECT_LT(r2, 1e-12);

  // The count first: OpenBLAS's openblas_set_num_threads restarts a stopped thread server (for its use after fork).
  ASSERT_TRUE(set_blas_thread_count(1));
  ASSERT_TRUE(stop_blas_threads());
  EXPECT_EQ(thread_count(), with_helpers - 1);  // OpenBLAS's one helper for 2 threads, joined
  const double r1 = relative_residual(a);
  EXPECT_GE(r1, 0);
  EXPECT_LT(r1, 1e-12);
  EXPECT_EQ(thread_count(), with_helpers - 1);  // one BLAS thread starts none

  ASSERT_TRUE(set_blas_thread_count(2));  // asked for again: restarted, and still right
  const double again = relative_residual(a);
  EXPECT_GE(again, 0);
  EXPECT_LT(again, 1e-12);
}

}  // namespace
}  // namespace wish::linalg
