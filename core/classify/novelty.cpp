#include "core/classify/novelty.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/errors.hpp"

namespace wish {
namespace {

// Mean of the k smallest entries of `d` (partially sorts it).
double mean_of_smallest(std::vector<double>& d, int k) {
  std::nth_element(d.begin(), d.begin() + (k - 1), d.end());
  double sum = 0;
  for (int i = 0; i < k; ++i) sum += d[static_cast<std::size_t>(i)];
  return sum / k;
}

}  // namespace

NoveltyCalibration calibrate_novelty(const Eigen::MatrixXd& Xs, int k, double quantile) {
  const Eigen::Index n = Xs.rows();
  if (n < 2) throw InvalidInputError("training_data", "novelty calibration needs at least 2 training samples");
  NoveltyCalibration c;
  c.k = std::max(1, std::min<int>(k, static_cast<int>(n) - 1));
  c.reference = Xs;
  c.quantile = quantile;
  std::vector<double> d;
  for (Eigen::Index i = 0; i < n; ++i) {
    d.clear();
    for (Eigen::Index j = 0; j < n; ++j)
      if (j != i) d.push_back((Xs.row(i) - Xs.row(j)).norm());
    c.loo_scores.push_back(mean_of_smallest(d, c.k));
  }
  std::sort(c.loo_scores.begin(), c.loo_scores.end());
  return c;
}

double novelty_threshold(const NoveltyCalibration& c, double quantile) {
  if (!(quantile > 0 && quantile < 1))
    throw InvalidInputError("invalid_parameter", "the novelty quantile must be between 0 and 1 (exclusive), got " +
                                                     std::to_string(quantile));
  const auto& s = c.loo_scores;
  const double pos = quantile * static_cast<double>(s.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, s.size() - 1);
  return s[lo] + (pos - static_cast<double>(lo)) * (s[hi] - s[lo]);
}

NoveltyAssessment assess_novelty(const NoveltyCalibration& c, const Eigen::Ref<const Eigen::VectorXd>& x, double quantile) {
  NoveltyAssessment a;
  a.quantile = quantile > 0 ? quantile : c.quantile;
  std::vector<double> d(static_cast<std::size_t>(c.reference.rows()));
  for (Eigen::Index j = 0; j < c.reference.rows(); ++j)
    d[static_cast<std::size_t>(j)] = (c.reference.row(j).transpose() - x).norm();
  a.score = mean_of_smallest(d, c.k);
  const auto at_least = c.loo_scores.end() - std::lower_bound(c.loo_scores.begin(), c.loo_scores.end(), a.score);
  a.p_value = (1.0 + static_cast<double>(at_least)) / (static_cast<double>(c.loo_scores.size()) + 1.0);
  a.threshold = novelty_threshold(c, a.quantile);
  a.novel = a.score > a.threshold;
  return a;
}

void validate_novelty(const NoveltyCalibration& c, Eigen::Index n_features) {
  auto bad = [](const std::string& m) { throw InvalidInputError("model_invalid", "invalid model file: novelty: " + m); };
  const Eigen::Index n = c.reference.rows();
  if (n < 2) bad("needs at least 2 reference samples");
  if (c.reference.cols() != n_features)
    bad("reference samples have " + std::to_string(c.reference.cols()) + " features, the model " + std::to_string(n_features));
  if (static_cast<Eigen::Index>(c.loo_scores.size()) != n)
    bad(std::to_string(c.loo_scores.size()) + " leave-one-out scores for " + std::to_string(n) + " reference samples");
  if (c.k < 1 || c.k >= n) bad("k = " + std::to_string(c.k) + " must be in 1.." + std::to_string(n - 1));
  if (!(c.quantile > 0 && c.quantile < 1)) bad("quantile must be between 0 and 1");
  if (!c.reference.allFinite() || !std::all_of(c.loo_scores.begin(), c.loo_scores.end(), [](double v) { return std::isfinite(v) && v >= 0; }))
    bad("non-finite or negative numbers");
  if (!std::is_sorted(c.loo_scores.begin(), c.loo_scores.end())) bad("leave-one-out scores are not ascending");
}

}  // namespace wish
