// CHOLMOD's hidden OpenMP: SuiteSparse 5's supernodal factorisation asks for num_threads(4) on large supernodes,
// overriding omp_set_num_threads(). The wrapper must keep those regions serial (the BLAS is where the threads belong)
// and leave the caller's OpenMP settings as they were. Own executable: it counts the threads of this process.
#include <filesystem>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "core/linalg/sparse_cholesky.hpp"

namespace wish::linalg {
namespace {

long thread_count() {
  long n = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) ++n;
  return n;
}

// Shifted 5-point Laplacian of an n×n grid: SPD, and at n = 150 its separators give supernodes far above CHOLMOD's
// "go parallel" thresholds (64 columns, 1024 entries).
Eigen::SparseMatrix<double> shifted_grid_laplacian(int n) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [n](int i, int j) { return i * n + j; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      t.emplace_back(id(i, j), id(i, j), 4.01);
      for (auto [di, dj] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}})
        if (i + di >= 0 && i + di < n && j + dj >= 0 && j + dj < n) t.emplace_back(id(i, j), id(i + di, j + dj), -1.0);
    }
  Eigen::SparseMatrix<double> l(n * n, n * n);
  l.setFromTriplets(t.begin(), t.end());
  return l;
}

TEST(CholmodThreads, SupernodalFactorisationStartsNoOpenMpThreadsAndRestoresTheCallersSettings) {
  omp_set_dynamic(0);
  omp_set_num_threads(3);
  const long threads_before = thread_count();
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
  EXPECT_EQ(thread_count(), threads_before);
  EXPECT_EQ(omp_get_dynamic(), 0);
  EXPECT_EQ(omp_get_max_threads(), 3);
}

}  // namespace
}  // namespace wish::linalg
