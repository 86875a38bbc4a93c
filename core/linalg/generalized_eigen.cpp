#include "core/linalg/generalized_eigen.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <Eigen/QR>

#include "core/linalg/sparse_cholesky.hpp"
#include "core/linalg/symmetric_eigen.hpp"

namespace wish::linalg {

const char* to_string(EigenStatus status) {
  switch (status) {
    case EigenStatus::Converged: return "converged";
    case EigenStatus::NotConverged: return "not_converged";
    case EigenStatus::FactorizationFailed: return "factorization_failed";
    case EigenStatus::InvalidInput: return "invalid_input";
  }
  return "?";
}

namespace {

// Orthonormal columns spanning `block` after removing its components along the columns of `basis` (classical
// Gram-Schmidt twice, then a thin Householder QR inside the block). Columns that vanish (the Krylov space is
// exhausted) are replaced by random ones orthogonalised the same way, so the basis keeps full rank.
Eigen::MatrixXd orthonormal_against(const Eigen::MatrixXd& basis, Eigen::MatrixXd block, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int pass = 0; pass < 2; ++pass) {
    if (basis.cols() > 0) block -= basis * (basis.transpose() * block);
    for (Eigen::Index j = 0; j < block.cols(); ++j) {
      const double norm = block.col(j).norm();
      if (!(norm > 1e-10)) {
        for (Eigen::Index i = 0; i < block.rows(); ++i) block(i, j) = uniform(rng);
        if (basis.cols() > 0) block.col(j) -= basis * (basis.transpose() * block.col(j));
      }
    }
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(block);
    block = qr.householderQ() * Eigen::MatrixXd::Identity(block.rows(), block.cols());
  }
  return block;
}

// Relative residual of each pair (see the header): |M^(-1/2)(L u - λ M u)| / ((λ + shift) |M^(1/2) u|).
Eigen::VectorXd relative_residuals(const Eigen::SparseMatrix<double>& L, const Eigen::VectorXd& mass,
                                   const Eigen::VectorXd& values, const Eigen::MatrixXd& vectors, double shift) {
  Eigen::VectorXd r(values.size());
  const Eigen::MatrixXd Lu = L * vectors;
  const Eigen::ArrayXd inv_sqrt = mass.array().rsqrt(), sqrt_m = mass.array().sqrt();
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    const Eigen::ArrayXd res = (Lu.col(i).array() - values(i) * mass.array() * vectors.col(i).array()) * inv_sqrt;
    const double unorm = (sqrt_m * vectors.col(i).array()).matrix().norm();
    r(i) = res.matrix().norm() / ((std::abs(values(i)) + shift) * std::max(unorm, 1e-300));
  }
  return r;
}

// Small problems: the dense eigendecomposition of M^(-1/2) L M^(-1/2).
GeneralizedEigenResult dense_solve(const Eigen::SparseMatrix<double>& L, const Eigen::VectorXd& mass, int count, double shift) {
  const Eigen::VectorXd s = mass.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd C = s.asDiagonal() * Eigen::MatrixXd(L) * s.asDiagonal();
  const SymmetricEigen eig = symmetric_eigen(0.5 * (C + C.transpose()));
  GeneralizedEigenResult r;
  if (!eig.converged) {
    r.status = EigenStatus::NotConverged;
    r.message = "dense symmetric eigensolver did not converge";
    return r;
  }
  const int k = std::min<int>(count, static_cast<int>(L.rows()));
  r.values = eig.values.head(k);
  r.vectors = s.asDiagonal() * eig.vectors.leftCols(k);
  r.residuals = relative_residuals(L, mass, r.values, r.vectors, shift);
  r.status = EigenStatus::Converged;
  return r;
}

}  // namespace

GeneralizedEigenResult smallest_generalized_eigenpairs(const Eigen::SparseMatrix<double>& L, const Eigen::VectorXd& mass,
                                                        const GeneralizedEigenOptions& options) {
  GeneralizedEigenResult result;
  const Eigen::Index n = L.rows();
  if (L.cols() != n || mass.size() != n || n < 1) {
    result.message = "L is " + std::to_string(L.rows()) + " x " + std::to_string(L.cols()) + " with " +
                     std::to_string(mass.size()) + " masses";
    return result;
  }
  if (!(mass.array() > 0).all() || !mass.allFinite()) {
    result.message = "the mass matrix has a non-positive or non-finite entry";
    return result;
  }
  if (options.count < 1 || !(options.shift > 0) || options.krylov_blocks < 1 || options.extra_columns < 0) {
    result.message = "count " + std::to_string(options.count) + ", shift " + std::to_string(options.shift) +
                     ", krylov_blocks " + std::to_string(options.krylov_blocks) + ": count and blocks must be >= 1, shift > 0";
    return result;
  }
  const int block = static_cast<int>(std::min<Eigen::Index>(options.count + options.extra_columns, n));
  if (n <= 3 * static_cast<Eigen::Index>(block) * options.krylov_blocks || n <= 64)
    return dense_solve(L, mass, options.count, options.shift);

  // A = L + shift M, factored once.
  Eigen::SparseMatrix<double> A = L;
  for (Eigen::Index i = 0; i < n; ++i) A.coeffRef(i, i) += options.shift * mass(i);
  A.makeCompressed();
  SparseCholesky cholesky;
  if (!cholesky.factorize(A)) {
    result.status = EigenStatus::FactorizationFailed;
    result.message = "L + shift M is not positive definite: " + cholesky.message();
    return result;
  }
  const Eigen::VectorXd sqrt_m = mass.cwiseSqrt();
  const auto apply_b = [&](const Eigen::MatrixXd& Y) -> Eigen::MatrixXd {
    return sqrt_m.asDiagonal() * cholesky.solve(sqrt_m.asDiagonal() * Y);
  };

  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd X(n, block);
  for (Eigen::Index j = 0; j < X.cols(); ++j)
    for (Eigen::Index i = 0; i < n; ++i) X(i, j) = uniform(rng);
  X = orthonormal_against(Eigen::MatrixXd(n, 0), X, rng);

  const int count = std::min<int>(options.count, block);
  for (int cycle = 1; cycle <= options.max_cycles; ++cycle) {
    result.cycles = cycle;
    // Krylov basis Q = [X, B X, ...] orthonormalised, and W = B Q.
    Eigen::MatrixXd Q(n, 0), W(n, 0), current = X;
    for (int s = 0; s < options.krylov_blocks; ++s) {
      const Eigen::MatrixXd q = s == 0 ? current : orthonormal_against(Q, current, rng);
      const Eigen::MatrixXd w = apply_b(q);
      Q.conservativeResize(n, Q.cols() + q.cols());
      Q.rightCols(q.cols()) = q;
      W.conservativeResize(n, W.cols() + w.cols());
      W.rightCols(w.cols()) = w;
      current = w;
    }
    const Eigen::MatrixXd T = Q.transpose() * W;
    const SymmetricEigen eig = symmetric_eigen(0.5 * (T + T.transpose()));
    if (!eig.converged) {
      result.status = EigenStatus::NotConverged;
      result.message = "the Rayleigh-Ritz eigensolver did not converge";
      return result;
    }
    // Eigen sorts ascending: the largest theta (smallest lambda) are the last columns.
    const Eigen::Index m = T.rows();
    Eigen::MatrixXd V(m, block);
    Eigen::VectorXd theta(block);
    for (int j = 0; j < block; ++j) {
      V.col(j) = eig.vectors.col(m - 1 - j);
      theta(j) = eig.values(m - 1 - j);
    }
    X = Q * V;
    if (!(theta.head(count).array() > 0).all()) {
      result.status = EigenStatus::NotConverged;
      result.message = "a Ritz value of the shift-inverted operator is not positive (L is not semidefinite?)";
      return result;
    }
    result.values = (theta.head(count).array().inverse() - options.shift).matrix();
    result.vectors = sqrt_m.cwiseInverse().asDiagonal() * X.leftCols(count);
    result.residuals = relative_residuals(L, mass, result.values, result.vectors, options.shift);
    if (result.residuals.maxCoeff() <= options.tolerance) {
      result.status = EigenStatus::Converged;
      result.message.clear();
      return result;
    }
  }
  result.status = EigenStatus::NotConverged;
  char text[160];
  std::snprintf(text, sizeof text, "largest relative residual %.3g after %d cycles (tolerance %.3g)",
                result.residuals.maxCoeff(), options.max_cycles, options.tolerance);
  result.message = text;
  return result;
}

}  // namespace wish::linalg
