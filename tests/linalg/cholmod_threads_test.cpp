// CHOLMOD's hidden OpenMP: SuiteSparse 5's supernodal factorisation asks for num_threads(4) on large supernodes,
// overriding omp_set_num_threads(). The wrapper must keep those regions serial (the BLAS is where the threads belong)
// and leave the caller's OpenMP settings as they were. It counts the threads of this process: ctest runs each test
// in a process of its own (gtest_discover_tests).
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "core/linalg/sparse_cholesky.hpp"
#include "tests/linalg/thread_test_support.hpp"

namespace wish::linalg {
namespace {

using test_support::process_thread_count;
using test_support::shifted_grid_laplacian;

TEST(CholmodThreads, SupernodalFactorisationStartsNoOpenMpThreadsAndRestoresTheCallersSettings) {
  omp_set_dynamic(0);
  omp_set_num_threads(3);
  const long threads_before = process_thread_count();
  const Eigen::SparseMatrix<double> a = shifted_grid_laplacian(150);
  CholeskyOptions options;
  options.cholmod_mode = CholmodMode::Supernodal;
  options.permutation = metis_ordering(a);
  SparseCholesky solver(options);
  ASSERT_TRUE(solver.factorize(a)) << solver.message();
  ASSERT_TRUE(solver.is_supernodal());
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(a.rows());
  const Eigen::VectorXd x = solver.solve(b);
  EXPECT_LT((a * x - b).norm(), 1e-10 * b.norm());
  // libgomp keeps the threads of a team alive after the region: any region that went parallel would show here.
  EXPECT_EQ(process_thread_count(), threads_before);
  EXPECT_EQ(omp_get_dynamic(), 0);
  EXPECT_EQ(omp_get_max_threads(), 3);
}

}  // namespace
}  // namespace wish::linalg
