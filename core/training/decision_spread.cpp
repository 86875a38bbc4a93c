#include "core/training/decision_spread.hpp"

#include <algorithm>
#include <limits>
#include <map>

namespace wish {

DecisionSpread::DecisionSpread(const std::vector<int>& model_labels) : labels_(model_labels) {
  const std::size_t k = labels_.size(), pairs = k * (k - (k > 0)) / 2;
  low_.assign(pairs, std::numeric_limits<double>::infinity());
  high_.assign(pairs, -std::numeric_limits<double>::infinity());
}

void DecisionSpread::add(int label, const std::vector<double>& decision) {
  const int k = static_cast<int>(labels_.size());
  const auto found = std::find(labels_.begin(), labels_.end(), label);
  if (found == labels_.end()) return;  // a class the fit never saw
  const int c = static_cast<int>(found - labels_.begin());
  int p = 0;  // libsvm's pair index: (0,1), (0,2), ..., (1,2), ...
  for (int a = 0; a < k; ++a)
    for (int b = a + 1; b < k; ++b, ++p) {
      if ((a != c && b != c) || p >= static_cast<int>(decision.size())) continue;
      low_[p] = std::min(low_[p], decision[p]);
      high_[p] = std::max(high_[p], decision[p]);
    }
}

double DecisionSpread::spread() const {
  double s = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < low_.size(); ++p)
    if (high_[p] >= low_[p]) s = std::min(s, high_[p] - low_[p]);
  return s;
}

double fit_decision_spread(const std::vector<int>& model_labels, const std::vector<int>& rows,
                           const std::vector<int>& labels, const std::function<std::vector<double>(int)>& decision) {
  std::map<int, std::vector<int>> by_class;  // positions in `rows`, in order
  for (std::size_t i = 0; i < rows.size(); ++i) by_class[labels[i]].push_back(static_cast<int>(i));
  DecisionSpread spread(model_labels);
  for (std::size_t k = 0;; ++k) {
    bool any = false;
    for (const auto& [label, positions] : by_class) {
      if (k >= positions.size()) continue;
      any = true;
      spread.add(label, decision(rows[static_cast<std::size_t>(positions[k])]));
    }
    if (!any || spread.settled()) break;
  }
  return spread.spread();
}

}  // namespace wish
