#include "core/geometry/cotan_laplacian.hpp"

#include <algorithm>

#include "core/geometry/face_geometry.hpp"

namespace wish::geometry {

void assemble_cotan_laplacian(const VertexPattern& pattern, const Eigen::MatrixX3i& faces, const Eigen::MatrixX3d& cot,
                              Eigen::SparseMatrix<double>& laplacian) {
  if (laplacian.nonZeros() != pattern.pattern.nonZeros() || laplacian.rows() != pattern.pattern.rows())
    laplacian = pattern.pattern;
  double* values = laplacian.valuePtr();
  std::fill(values, values + laplacian.nonZeros(), 0.0);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const auto& s = pattern.slot[static_cast<size_t>(f)];
    for (int k = 0; k < 3; ++k) {
      // Corner k is opposite the edge (k+1, k+2).
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      const double w = 0.5 * cot(f, k);
      values[s[static_cast<size_t>(3 * a + b)]] -= w;
      values[s[static_cast<size_t>(3 * b + a)]] -= w;
      values[s[static_cast<size_t>(3 * a + a)]] += w;
      values[s[static_cast<size_t>(3 * b + b)]] += w;
    }
  }
}

Eigen::SparseMatrix<double> cotan_laplacian(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
  const VertexPattern pattern = build_vertex_pattern(vertices.rows(), faces);
  Eigen::SparseMatrix<double> laplacian = pattern.pattern;
  assemble_cotan_laplacian(pattern, faces, corner_cotangents(vertices, faces), laplacian);
  return laplacian;
}

}  // namespace wish::geometry
