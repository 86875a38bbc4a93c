#include "core/classify/classifier_model.hpp"

#include <algorithm>
#include <cmath>

#include "core/classify/classifier_state.hpp"
#include "core/classify/feature_pipeline.hpp"
#include "core/common/errors.hpp"

namespace wish {

ClassifierModel::ClassifierModel(std::shared_ptr<const State> state) : state_(std::move(state)) {
  if (!state_) throw InvalidInputError("model_invalid", "empty classifier model");
}

const std::string& ClassifierModel::name() const { return state_->name; }
const std::string& ClassifierModel::version() const { return state_->version; }
const std::vector<std::string>& ClassifierModel::classes() const { return state_->classes; }
const DescriptorRecipe& ClassifierModel::recipe() const { return state_->recipe; }
const TrainingSummary& ClassifierModel::training_summary() const { return state_->summary; }
const std::string& ClassifierModel::payload_sha256() const { return state_->payload_sha256; }

bool ClassifierModel::has_novelty() const { return state_->novelty.has_value(); }
const NoveltyCalibration* ClassifierModel::novelty_calibration() const {
  return state_->novelty ? &*state_->novelty : nullptr;
}

Prediction ClassifierModel::predict(const ShapeFeatures& features, const PredictOptions& options) const {
  const State& s = *state_;
  const Eigen::VectorXd x = s.scaler.transform(apply_feature_pipeline(features, s.recipe.features));
  const SvmOutput out = s.svm.predict(x);
  const int k = static_cast<int>(s.classes.size());
  Prediction p;
  p.label = s.classes.at(out.label);
  std::vector<double> prob = out.probability;
  if (prob.empty()) {  // a model without Platt calibration: report vote shares instead
    prob.assign(k, 0.0);
    for (int i = 0; i < k; ++i) prob[i] = out.votes[i] / (k * (k - 1) / 2.0);
  }
  for (int i = 0; i < k; ++i) p.probabilities.emplace_back(s.classes[i], prob[i]);
  // Runner-up: most votes among the others, ties broken by probability; margin = the pairwise decision value
  // of winner vs runner-up, positive when the winner won that duel.
  const int w = out.label;
  int r = -1;
  for (int i = 0; i < k; ++i) {
    if (i == w) continue;
    if (r < 0 || out.votes[i] > out.votes[r] || (out.votes[i] == out.votes[r] && prob[i] > prob[r])) r = i;
  }
  const int a = std::min(w, r), b = std::max(w, r);
  const double d = out.decision[a * k - a * (a + 1) / 2 + (b - a - 1)];
  p.margin = w == a ? d : -d;
  if (s.novelty) p.novelty = assess_novelty(*s.novelty, x, options.novelty_quantile, w);
  return p;
}

}  // namespace wish
