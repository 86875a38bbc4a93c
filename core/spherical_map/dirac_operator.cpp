#include "core/spherical_map/dirac_operator.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "core/geometry/face_geometry.hpp"
#include "core/spherical_map/quaternion.hpp"

namespace wish::spherical {
namespace {

using Complex = std::complex<double>;

// Adds the block of left multiplication by q at b (column c at b + c·stride).
inline void add_block(double* b, int stride, const Quaternion& q) {
  b[0] += q.w, b[1] += q.x, b[2] += q.y, b[3] += q.z;
  b += stride;
  b[0] -= q.x, b[1] += q.w, b[2] += q.z, b[3] -= q.y;
  b += stride;
  b[0] -= q.y, b[1] -= q.z, b[2] += q.w, b[3] += q.x;
  b += stride;
  b[0] -= q.z, b[1] += q.y, b[2] -= q.x, b[3] += q.w;
}

inline void add_block(Complex* b, int stride, const Quaternion& q) {
  const Complex z1(q.w, q.x), z2(q.y, -q.z);
  b[0] += z1, b[1] += z2;
  b += stride;
  b[0] -= std::conj(z2), b[1] += std::conj(z1);
}

}  // namespace

template <class Scalar>
DiracPatternT<Scalar> build_dirac_pattern(const geometry::VertexPattern& vertex_pattern, const std::vector<int>& order) {
  constexpr int B = DiracPatternT<Scalar>::kBlock;
  const Eigen::SparseMatrix<double>& p = vertex_pattern.pattern;
  const int n = static_cast<int>(p.rows());
  if (!order.empty() && order.size() != static_cast<size_t>(n))
    throw std::invalid_argument("build_dirac_pattern: the order must list every vertex once");
  std::vector<int> position(static_cast<size_t>(n));  // block position of each vertex
  for (int k = 0; k < n; ++k) position[static_cast<size_t>(order.empty() ? k : order[static_cast<size_t>(k)])] = k;
  // Block column k (vertex j = order[k]) keeps the entries (i, j) with position[i] >= k, rows by position.
  std::vector<long> lower_count(static_cast<size_t>(n), 0);
  long lower_nnz = 0;
  for (int j = 0; j < n; ++j) {
    for (int q = p.outerIndexPtr()[j]; q < p.outerIndexPtr()[j + 1]; ++q)
      if (position[static_cast<size_t>(p.innerIndexPtr()[q])] >= position[static_cast<size_t>(j)])
        ++lower_count[static_cast<size_t>(j)];
    lower_nnz += lower_count[static_cast<size_t>(j)];
  }
  DiracPatternT<Scalar> out;
  out.order = order;
  Eigen::SparseMatrix<Scalar>& m = out.matrix;
  m.resize(B * n, B * n);
  m.reserve(B * B * lower_nnz);
  m.resizeNonZeros(B * B * lower_nnz);
  out.block_base.assign(static_cast<size_t>(p.nonZeros()), -1);
  out.block_stride.assign(static_cast<size_t>(p.nonZeros()), 0);
  int* outer = m.outerIndexPtr();
  int* inner = m.innerIndexPtr();
  long offset = 0;  // value index of the first block of block column k
  std::vector<std::pair<int, int>> rows;  // (block row, vertex-pattern index) of one column
  for (int k = 0; k < n; ++k) {
    const int j = order.empty() ? k : order[static_cast<size_t>(k)];
    rows.clear();
    for (int q = p.outerIndexPtr()[j]; q < p.outerIndexPtr()[j + 1]; ++q) {
      const int row = position[static_cast<size_t>(p.innerIndexPtr()[q])];
      if (row >= k) rows.emplace_back(row, q);
    }
    std::sort(rows.begin(), rows.end());
    const int count = static_cast<int>(rows.size());
    for (int c = 0; c < B; ++c) {
      const int start = static_cast<int>(offset) + c * B * count;
      outer[B * k + c] = start;
      for (int t = 0; t < count; ++t)
        for (int r = 0; r < B; ++r) inner[start + B * t + r] = B * rows[static_cast<size_t>(t)].first + r;
    }
    for (int t = 0; t < count; ++t) {
      const size_t q = static_cast<size_t>(rows[static_cast<size_t>(t)].second);
      out.block_base[q] = static_cast<int>(offset) + B * t;
      out.block_stride[q] = B * count;
    }
    offset += static_cast<long>(B) * B * count;
  }
  outer[B * n] = static_cast<int>(offset);
  std::fill(m.valuePtr(), m.valuePtr() + m.nonZeros(), Scalar(0));
  return out;
}

template <class Scalar>
double assemble_dirac(const geometry::VertexPattern& vertex_pattern, DiracPatternT<Scalar>& pattern,
                      const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces, const Eigen::VectorXd& areas,
                      const Eigen::VectorXd& rho) {
  Scalar* values = pattern.matrix.valuePtr();
  std::fill(values, values + pattern.matrix.nonZeros(), Scalar(0));
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
        // 𝔼[i_k, i_l] += −(1/(4A)) e_k e_l + (1/6)(ρ_k e_l − ρ_l e_k) + (A/9) ρ_k ρ_l
        const size_t s = static_cast<size_t>(slot[static_cast<size_t>(3 * k + l)]);
        if (pattern.block_base[s] < 0) continue;  // block above the diagonal: not stored (its adjoint is)
        const Quaternion q = (-1.0 / (4.0 * area)) * (e[k] * e[l]) + (1.0 / 6.0) * (r[k] * e[l] - r[l] * e[k]) +
                             Quaternion::real(area / 9.0 * r[k] * r[l]);
        add_block(values + pattern.block_base[s], pattern.block_stride[s], q);
      }
    }
  }
  // Diagonal blocks are real: the (0, 0) element of each is the common diagonal value.
  double diag = 0;
  const Eigen::Index nv = vertex_pattern.pattern.rows();
  for (Eigen::Index i = 0; i < nv; ++i) {
    const size_t s = static_cast<size_t>(vertex_pattern.diagonal[static_cast<size_t>(i)]);
    diag += std::real(values[pattern.block_base[s]]);
  }
  return diag / static_cast<double>(nv);
}

template DiracPatternT<double> build_dirac_pattern<double>(const geometry::VertexPattern&, const std::vector<int>&);
template DiracPatternT<Complex> build_dirac_pattern<Complex>(const geometry::VertexPattern&, const std::vector<int>&);
template double assemble_dirac<double>(const geometry::VertexPattern&, DiracPatternT<double>&, const Eigen::MatrixX3d&,
                                       const Eigen::MatrixX3i&, const Eigen::VectorXd&, const Eigen::VectorXd&);
template double assemble_dirac<Complex>(const geometry::VertexPattern&, DiracPatternT<Complex>&, const Eigen::MatrixX3d&,
                                        const Eigen::MatrixX3i&, const Eigen::VectorXd&, const Eigen::VectorXd&);

namespace {

// Both triangles from the stored lower one (the strictly-upper entries of diagonal blocks are not read).
template <class Scalar>
Eigen::SparseMatrix<Scalar> full_hermitian(const Eigen::SparseMatrix<Scalar>& stored) {
  const Eigen::SparseMatrix<Scalar> lower = stored.template triangularView<Eigen::Lower>();
  const Eigen::SparseMatrix<Scalar> strictly_lower = stored.template triangularView<Eigen::StrictlyLower>();
  return lower + Eigen::SparseMatrix<Scalar>(strictly_lower.adjoint());
}

template <class Scalar>
Eigen::SparseMatrix<Scalar> assembled_full(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                           const Eigen::VectorXd& rho) {
  const geometry::VertexPattern vp = geometry::build_vertex_pattern(vertices.rows(), faces);
  DiracPatternT<Scalar> dp = build_dirac_pattern<Scalar>(vp);
  assemble_dirac(vp, dp, vertices, faces, geometry::face_areas(vertices, faces), rho);
  return full_hermitian(dp.matrix);
}

}  // namespace

Eigen::SparseMatrix<double> dirac_matrix(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                         const Eigen::VectorXd& rho) {
  return assembled_full<double>(vertices, faces, rho);
}

Eigen::SparseMatrix<Complex> dirac_matrix_complex(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                                  const Eigen::VectorXd& rho) {
  return assembled_full<Complex>(vertices, faces, rho);
}

Eigen::VectorXd quaternions_from_complex(const Eigen::VectorXcd& v, const std::vector<int>& order) {
  const Eigen::Index n = v.size() / 2;
  Eigen::VectorXd q(4 * n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index i = order.empty() ? k : order[static_cast<size_t>(k)];
    q[4 * i] = v[2 * k].real();
    q[4 * i + 1] = v[2 * k].imag();
    q[4 * i + 2] = v[2 * k + 1].real();
    q[4 * i + 3] = -v[2 * k + 1].imag();
  }
  return q;
}

Eigen::VectorXd quaternions_from_permuted(const Eigen::VectorXd& q, const std::vector<int>& order) {
  if (order.empty()) return q;
  Eigen::VectorXd out(q.size());
  for (size_t k = 0; k < order.size(); ++k) out.segment<4>(4 * order[k]) = q.segment<4>(4 * static_cast<Eigen::Index>(k));
  return out;
}

Eigen::VectorXcd complex_from_quaternions(const Eigen::VectorXd& q) {
  const Eigen::Index n = q.size() / 4;
  Eigen::VectorXcd v(2 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    v[2 * i] = Complex(q[4 * i], q[4 * i + 1]);
    v[2 * i + 1] = Complex(q[4 * i + 2], -q[4 * i + 3]);
  }
  return v;
}

}  // namespace wish::spherical
