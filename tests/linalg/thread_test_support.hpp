// Helpers of the tests that count this process's threads around a factorisation (cholmod_threads_test,
// blas_threads_test). Each test runs in its own process (gtest_discover_tests), so the count is the test's own.
#pragma once

#include <filesystem>
#include <utility>
#include <vector>

#include <Eigen/SparseCore>

namespace wish::linalg::test_support {

// Threads of this process now (/proc/self/task has one entry per thread).
inline long process_thread_count() {
  long n = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) ++n;
  return n;
}

// Shifted 5-point Laplacian of an n×n grid: SPD, and at n = 150 its separators give supernodes far above CHOLMOD's
// "go parallel" thresholds (64 columns, 1024 entries) and BLAS calls large enough for OpenBLAS to use its threads.
inline Eigen::SparseMatrix<double> shifted_grid_laplacian(int n) {
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

}  // namespace wish::linalg::test_support
