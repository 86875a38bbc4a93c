#include "core/geometry/vertex_pattern.hpp"

#include <algorithm>

namespace wish::geometry {

VertexPattern build_vertex_pattern(Eigen::Index vertex_count, const Eigen::MatrixX3i& faces) {
  const int n = static_cast<int>(vertex_count);
  // Column lists of neighbours (row indices), diagonal included.
  std::vector<std::vector<int>> columns(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) columns[static_cast<size_t>(i)].push_back(i);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l)
        if (k != l) columns[static_cast<size_t>(faces(f, l))].push_back(faces(f, k));
  VertexPattern out;
  Eigen::SparseMatrix<double>& a = out.pattern;
  a.resize(n, n);
  std::vector<int> outer(static_cast<size_t>(n) + 1, 0);
  long nnz = 0;
  for (int j = 0; j < n; ++j) {
    auto& c = columns[static_cast<size_t>(j)];
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
    nnz += static_cast<long>(c.size());
  }
  a.reserve(nnz);
  a.resizeNonZeros(nnz);
  int pos = 0;
  out.diagonal.resize(static_cast<size_t>(n));
  for (int j = 0; j < n; ++j) {
    a.outerIndexPtr()[j] = pos;
    for (int i : columns[static_cast<size_t>(j)]) {
      if (i == j) out.diagonal[static_cast<size_t>(j)] = pos;
      a.innerIndexPtr()[pos] = i;
      a.valuePtr()[pos] = 0.0;
      ++pos;
    }
  }
  a.outerIndexPtr()[n] = pos;
  out.edge_count = (nnz - n) / 2;
  out.slot.resize(static_cast<size_t>(faces.rows()));
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      for (int l = 0; l < 3; ++l) {
        const int row = faces(f, k), col = faces(f, l);
        const int* begin = a.innerIndexPtr() + a.outerIndexPtr()[col];
        const int* end = a.innerIndexPtr() + a.outerIndexPtr()[col + 1];
        out.slot[static_cast<size_t>(f)][static_cast<size_t>(3 * k + l)] =
            static_cast<int>(std::lower_bound(begin, end, row) - a.innerIndexPtr());
      }
    }
  }
  return out;
}

}  // namespace wish::geometry
