#include "core/training/metrics.hpp"

#include "core/common/errors.hpp"

namespace wish {

double accuracy(const std::vector<int>& truth, const std::vector<int>& predicted) {
  if (truth.size() != predicted.size() || truth.empty()) return 0;
  std::size_t correct = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) correct += truth[i] == predicted[i];
  return static_cast<double>(correct) / static_cast<double>(truth.size());
}

ClassificationMetrics evaluate_predictions(const std::vector<int>& truth, const std::vector<int>& predicted,
                                           const std::vector<std::string>& classes) {
  const int k = static_cast<int>(classes.size());
  if (truth.size() != predicted.size()) throw InvalidInputError("training_data", "truth and prediction sizes differ");
  ClassificationMetrics m;
  m.confusion.setZero(k, k);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (truth[i] < 0 || truth[i] >= k || predicted[i] < 0 || predicted[i] >= k)
      throw InvalidInputError("training_data", "class index out of range");
    ++m.confusion(truth[i], predicted[i]);
  }
  m.accuracy = accuracy(truth, predicted);
  for (int c = 0; c < k; ++c) {
    ClassMetrics cm;
    cm.label = classes[c];
    const int tp = m.confusion(c, c);
    const int predicted_c = m.confusion.col(c).sum();
    cm.support = m.confusion.row(c).sum();
    cm.precision = predicted_c > 0 ? static_cast<double>(tp) / predicted_c : 0;
    cm.recall = cm.support > 0 ? static_cast<double>(tp) / cm.support : 0;
    cm.f1 = cm.precision + cm.recall > 0 ? 2 * cm.precision * cm.recall / (cm.precision + cm.recall) : 0;
    m.macro_f1 += cm.f1 / k;
    m.per_class.push_back(cm);
  }
  return m;
}

}  // namespace wish
