// stop_blas_threads (core/common/thread_policy.hpp): OpenBLAS's helper threads are gone afterwards, and the BLAS
// still computes — on one thread, and on two again once asked for (it restarts its threads). It counts the threads
// of this process: ctest runs each test in a process of its own (gtest_discover_tests).
#include <vector>

#include <gtest/gtest.h>

#include "core/common/thread_policy.hpp"
#include "core/linalg/blas_info.hpp"
#include "core/linalg/sparse_cholesky.hpp"
#include "tests/linalg/thread_test_support.hpp"

namespace wish::linalg {
namespace {

using test_support::process_thread_count;
using test_support::shifted_grid_laplacian;

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
  const long with_helpers = process_thread_count();
  ASSERT_GE(with_helpers, 2) << "OpenBLAS started no helper thread for 2 threads";
  const double r2 = relative_residual(a);
  EXPECT_GE(r2, 0);
  EXPECT_LT(r2, 1e-12);

  // The count first: OpenBLAS's openblas_set_num_threads restarts a stopped thread server (for its use after fork).
  ASSERT_TRUE(set_blas_thread_count(1));
  ASSERT_TRUE(stop_blas_threads());
  EXPECT_EQ(process_thread_count(), with_helpers - 1);  // OpenBLAS's one helper for 2 threads, joined
  const double r1 = relative_residual(a);
  EXPECT_GE(r1, 0);
  EXPECT_LT(r1, 1e-12);
  EXPECT_EQ(process_thread_count(), with_helpers - 1);  // one BLAS thread starts none

  ASSERT_TRUE(set_blas_thread_count(2));  // asked for again: restarted, and still right
  const double again = relative_residual(a);
  EXPECT_GE(again, 0);
  EXPECT_LT(again, 1e-12);
}

}  // namespace
}  // namespace wish::linalg
