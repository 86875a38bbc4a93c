#include "core/spherical_map/dirac_operator.hpp"

#include <algorithm>

#include "core/geometry/face_geometry.hpp"
#include "core/spherical_map/quaternion.hpp"

namespace wish::spherical {

DiracPattern build_dirac_pattern(const geometry::VertexPattern& vertex_pattern) {
  const Eigen::SparseMatrix<double>& p = vertex_pattern.pattern;
  const int n = static_cast<int>(p.rows());
  const long nnz = p.nonZeros();
  DiracPattern out;
  Eigen::SparseMatrix<double>& m = out.matrix;
  m.resize(4 * n, 4 * n);
  m.reserve(16 * nnz);
  m.resizeNonZeros(16 * nnz);
  out.block_base.resize(static_cast<size_t>(nnz));
  out.block_stride.resize(static_cast<size_t>(nnz));
  int* outer = m.outerIndexPtr();
  int* inner = m.innerIndexPtr();
  for (int j = 0; j < n; ++j) {
    const int begin = p.outerIndexPtr()[j], end = p.outerIndexPtr()[j + 1];
    const int count = end - begin;
    for (int c = 0; c < 4; ++c) {
      const int start = 16 * begin + c * 4 * count;
      outer[4 * j + c] = start;
      for (int q = begin; q < end; ++q) {
        const int i = p.innerIndexPtr()[q];
        for (int r = 0; r < 4; ++r) inner[start + 4 * (q - begin) + r] = 4 * i + r;
      }
    }
    for (int q = begin; q < end; ++q) {
      out.block_base[static_cast<size_t>(q)] = 16 * begin + 4 * (q - begin);
      out.block_stride[static_cast<size_t>(q)] = 4 * count;
    }
  }
  outer[4 * n] = static_cast<int>(16 * nnz);
  std::fill(m.valuePtr(), m.valuePtr() + m.nonZeros(), 0.0);
  return out;
}

double assemble_dirac(const geometry::VertexPattern& vertex_pattern, DiracPattern& pattern,
                      const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces, const Eigen::VectorXd& areas,
                      const Eigen::VectorXd& rho) {
  double* values = pattern.matrix.valuePtr();
  std::fill(values, values + pattern.matrix.nonZeros(), 0.0);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const int idx[3] = {faces(f, 0), faces(f, 1), faces(f, 2)};
    const double area = areas[f];
    Quaternion e[3];
    for (int k = 0; k < 3; ++k)
      e[k] = Quaternion::imaginary(vertices.row(idx[(k + 2) % 3]) - vertices.row(idx[(k + 1) % 3]));
    const double r[3] = {rho[idx[0]], rho[idx[1]], rho[idx[2]]};
    const auto& slot = vertex_pattern.slot[static_cast<size_t>(f)];
    for (int k = 0; k < 3; ++k) {
      for (int l = 0; l < 3; ++l) {
        const Quaternion q = (-1.0 / (4.0 * area)) * (e[k] * e[l]) + (1.0 / 6.0) * (r[k] * e[l] - r[l] * e[k]) +
                             Quaternion::real(area / 9.0 * r[k] * r[l]);
        const size_t s = static_cast<size_t>(slot[static_cast<size_t>(3 * k + l)]);
        double* b = values + pattern.block_base[s];
        const int stride = pattern.block_stride[s];
        // Column-major write of left_block(q): column c at b + c·stride, rows 0..3.
        b[0] += q.w, b[1] += q.x, b[2] += q.y, b[3] += q.z;
        b += stride;
        b[0] -= q.x, b[1] += q.w, b[2] += q.z, b[3] -= q.y;
        b += stride;
        b[0] -= q.y, b[1] -= q.z, b[2] += q.w, b[3] += q.x;
        b += stride;
        b[0] -= q.z, b[1] += q.y, b[2] -= q.x, b[3] += q.w;
      }
    }
  }
  double diag = 0;
  const Eigen::Index n4 = pattern.matrix.rows();
  for (Eigen::Index i = 0; i < n4 / 4; ++i) {
    const size_t s = static_cast<size_t>(vertex_pattern.diagonal[static_cast<size_t>(i)]);
    diag += 4.0 * values[pattern.block_base[s]];  // diagonal blocks are real: 4 equal diagonal entries
  }
  return diag / static_cast<double>(n4);
}

Eigen::SparseMatrix<double> dirac_matrix(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                         const Eigen::VectorXd& rho) {
  const geometry::VertexPattern vp = geometry::build_vertex_pattern(vertices.rows(), faces);
  DiracPattern dp = build_dirac_pattern(vp);
  assemble_dirac(vp, dp, vertices, faces, geometry::face_areas(vertices, faces), rho);
  return dp.matrix;
}

}  // namespace wish::spherical
