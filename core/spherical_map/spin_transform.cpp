#include "core/spherical_map/spin_transform.hpp"

#include <chrono>
#include <cmath>
#include <complex>
#include <type_traits>

#include "core/common/elapsed.hpp"
#include "core/linalg/lower_hermitian_product.hpp"
#include "core/spherical_map/quaternion.hpp"

namespace wish::spherical {
namespace {

Quaternion lambda_at(const Eigen::VectorXd& lambda, int i) {
  return {lambda[4 * i], lambda[4 * i + 1], lambda[4 * i + 2], lambda[4 * i + 3]};
}

}  // namespace

template <class Scalar>
EigenSolveReport smallest_eigenvector(linalg::SparseCholeskyT<Scalar>& solver, const Eigen::SparseMatrix<Scalar>& dirac,
                                      double mean_diagonal, const EigenSolveOptions& options,
                                      Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& x) {
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  constexpr int block = std::is_same_v<Scalar, double> ? 4 : 2;
  EigenSolveReport report;
  auto t0 = std::chrono::steady_clock::now();
  double shift = options.relative_shift * mean_diagonal;
  bool factored = false;
  for (int attempt = 0; attempt <= options.max_shift_retries; ++attempt) {
    if (solver.factorize(dirac, shift)) {
      factored = true;
      break;
    }
    report.message = solver.message();
    shift *= options.shift_growth;
  }
  report.factor_seconds = seconds_since(t0);
  report.shift = shift;
  if (!factored) {
    report.message = "Dirac factorisation failed after " + std::to_string(options.max_shift_retries) +
                     " shift increases: " + report.message;
    return report;
  }
  t0 = std::chrono::steady_clock::now();
  const Eigen::Index n4 = dirac.rows();
  x = Vector::Zero(n4);
  for (Eigen::Index i = 0; i < n4; i += block) x[i] = Scalar(1.0);
  x.normalize();
  Vector ex;
  for (int it = 1; it <= std::max(1, options.max_iterations); ++it) {
    x = solver.solve(x).col(0);
    const double norm = x.norm();
    if (!std::isfinite(norm) || norm == 0) {
      report.message = "inverse iteration produced a non-finite or zero vector";
      report.solve_seconds = seconds_since(t0);
      return report;
    }
    x /= norm;
    ex = linalg::lower_hermitian_times(dirac, x);
    const double gamma = std::real(x.dot(ex));  // xᴴ𝔼x, real for Hermitian 𝔼
    report.iterations = it;
    report.rayleigh = gamma / mean_diagonal;
    report.residual = (ex - gamma * x).norm() / mean_diagonal;
    if (report.residual <= options.residual_tolerance) break;
  }
  report.solve_seconds = seconds_since(t0);
  report.ok = std::isfinite(report.residual);
  if (!report.ok) report.message = "non-finite eigen residual";
  return report;
}

template EigenSolveReport smallest_eigenvector<double>(linalg::SparseCholeskyT<double>&,
                                                      const Eigen::SparseMatrix<double>&, double,
                                                      const EigenSolveOptions&, Eigen::VectorXd&);
template EigenSolveReport smallest_eigenvector<std::complex<double>>(
    linalg::SparseCholeskyT<std::complex<double>>&, const Eigen::SparseMatrix<std::complex<double>>&, double,
    const EigenSolveOptions&, Eigen::VectorXcd&);

Eigen::MatrixX3d spin_divergence(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                 const Eigen::MatrixX3d& cot, const Eigen::VectorXd& lambda) {
  Eigen::MatrixX3d omega = Eigen::MatrixX3d::Zero(vertices.rows(), 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      // Edge (a, b) opposite corner k, oriented a → b.
      const int a = faces(f, (k + 1) % 3), b = faces(f, (k + 2) % 3);
      const Quaternion e = Quaternion::imaginary(vertices.row(b) - vertices.row(a));
      const Quaternion la = lambda_at(lambda, a), lb = lambda_at(lambda, b);
      const Quaternion ea = e * la, eb = e * lb;
      // ẽ = (1/3) λ̄a e λa + (1/6) λ̄a e λb + (1/6) λ̄b e λa + (1/3) λ̄b e λb   (imaginary)
      const Quaternion et = (1.0 / 3.0) * (la.conj() * ea) + (1.0 / 6.0) * (la.conj() * eb) +
                            (1.0 / 6.0) * (lb.conj() * ea) + (1.0 / 3.0) * (lb.conj() * eb);
      const Eigen::Vector3d v = 0.5 * cot(f, k) * et.vec();
      omega.row(a) -= v.transpose();
      omega.row(b) += v.transpose();
    }
  }
  return omega;
}

Eigen::MatrixX3d spin_divergence(const Eigen::MatrixX3d& vertices, const std::vector<geometry::IntrinsicEdgeWeight>& edges,
                                 const Eigen::VectorXd& lambda) {
  Eigen::MatrixX3d omega = Eigen::MatrixX3d::Zero(vertices.rows(), 3);
  for (const geometry::IntrinsicEdgeWeight& edge : edges) {
    const int a = edge.i, b = edge.j;
    const Quaternion e = Quaternion::imaginary(vertices.row(b) - vertices.row(a));
    const Quaternion la = lambda_at(lambda, a), lb = lambda_at(lambda, b);
    const Quaternion ea = e * la, eb = e * lb;
    const Quaternion et = (1.0 / 3.0) * (la.conj() * ea) + (1.0 / 6.0) * (la.conj() * eb) +
                          (1.0 / 6.0) * (lb.conj() * ea) + (1.0 / 3.0) * (lb.conj() * eb);
    const Eigen::Vector3d v = edge.weight * et.vec();
    omega.row(a) -= v.transpose();
    omega.row(b) += v.transpose();
  }
  return omega;
}

void pin_vertex(const Eigen::SparseMatrix<double>& laplacian, int pin, Eigen::SparseMatrix<double>& pinned) {
  pinned = laplacian;
  const int* outer = pinned.outerIndexPtr();
  const int* inner = pinned.innerIndexPtr();
  double* values = pinned.valuePtr();
  for (Eigen::Index j = 0; j < pinned.cols(); ++j) {
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      const bool in_row_or_column = inner[p] == pin || j == pin;
      if (!in_row_or_column) continue;
      values[p] = (inner[p] == j) ? 1.0 : 0.0;
    }
  }
}

}  // namespace wish::spherical
