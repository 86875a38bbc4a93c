#pragma once
// Classification figures the paper did not report but docs/design/classification.md asks for: confusion matrix and
// per-class precision / recall / F1 (scikit-learn's definitions; 0 when undefined, as zero_division=0).

#include <string>
#include <vector>

#include <Eigen/Core>

namespace wish {

struct ClassMetrics {
  std::string label;
  double precision = 0, recall = 0, f1 = 0;
  int support = 0;  // true samples of the class
};

struct ClassificationMetrics {
  double accuracy = 0;
  Eigen::MatrixXi confusion;  // rows: true class, columns: predicted class
  std::vector<ClassMetrics> per_class;
  double macro_f1 = 0;
};

ClassificationMetrics evaluate_predictions(const std::vector<int>& truth, const std::vector<int>& predicted,
                                           const std::vector<std::string>& classes);

double accuracy(const std::vector<int>& truth, const std::vector<int>& predicted);

}  // namespace wish
