#pragma once
// z-score standardisation fitted on training data only (docs/design/classification.md, feature pipeline), identical to
// scikit-learn's StandardScaler: population standard deviation (ddof = 0), and a scale of 1 for a constant
// column so that it maps to 0 instead of dividing by zero.

#include <Eigen/Core>

namespace wish {

struct StandardScaler {
  Eigen::VectorXd mean, scale;

  static StandardScaler fit(const Eigen::MatrixXd& X);  // one sample per row
  Eigen::VectorXd transform(const Eigen::VectorXd& x) const { return (x - mean).cwiseQuotient(scale); }
  Eigen::MatrixXd transform(const Eigen::MatrixXd& X) const;
};

}  // namespace wish
