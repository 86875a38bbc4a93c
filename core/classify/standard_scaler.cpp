#include "core/classify/standard_scaler.hpp"

#include <cmath>
#include <limits>

namespace wish {

StandardScaler StandardScaler::fit(const Eigen::MatrixXd& X) {
  StandardScaler s;
  s.mean = X.colwise().mean().transpose();
  s.scale.resize(X.cols());
  for (Eigen::Index j = 0; j < X.cols(); ++j) {
    const double var = (X.col(j).array() - s.mean(j)).square().mean();
    const double sd = std::sqrt(var);
    // scikit-learn's _handle_zeros_in_scale: near-constant columns keep scale 1.
    s.scale(j) = sd < 10 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(s.mean(j))) ? 1.0 : sd;
  }
  return s;
}

Eigen::MatrixXd StandardScaler::transform(const Eigen::MatrixXd& X) const {
  Eigen::MatrixXd out = X;
  for (Eigen::Index i = 0; i < X.rows(); ++i) out.row(i) = transform(Eigen::VectorXd(X.row(i).transpose())).transpose();
  return out;
}

}  // namespace wish
