#include "core/classify/novelty.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/classify/splits.hpp"
#include "core/common/errors.hpp"
#include "core/linalg/symmetric_eigen.hpp"

namespace wish {

const char* to_string(NoveltyRule rule) { return kNoveltyRuleNames.name(rule); }

namespace {

// Mean of the k smallest entries of `d` (partially sorts it).
double mean_of_smallest(std::vector<double>& d, int k) {
  std::nth_element(d.begin(), d.begin() + (k - 1), d.end());
  double sum = 0;
  for (int i = 0; i < k; ++i) sum += d[static_cast<std::size_t>(i)];
  return sum / k;
}

int group_count(const NoveltyCalibration& c) { return static_cast<int>(c.loo_scores.size()); }

std::vector<Eigen::Index> rows_of_group(const NoveltyCalibration& c, int g) {
  std::vector<Eigen::Index> rows;
  for (std::size_t i = 0; i < c.reference_class.size(); ++i)
    if (c.reference_class[i] == g) rows.push_back(static_cast<Eigen::Index>(i));
  return rows;
}

// k of a group of n rows: the calibration's k, at most n - 1 (a leave-one-out score needs k other members); a group
// of one row uses its one row.
int group_k(const NoveltyCalibration& c, std::size_t n) {
  return std::max(1, std::min(c.k, static_cast<int>(n) - 1));
}

void check_quantile(double quantile) {
  if (!(quantile > 0 && quantile < 1))
    throw InvalidInputError("invalid_parameter", "the novelty quantile must be between 0 and 1 (exclusive), got " +
                                                     std::to_string(quantile));
}

double quantile_of(const std::vector<double>& s, double quantile) {
  const double pos = quantile * static_cast<double>(s.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, s.size() - 1);
  return s[lo] + (pos - static_cast<double>(lo)) * (s[hi] - s[lo]);
}

// The reference rows in the space distances are measured in: whitened (each row times W; W is symmetric) or as stored.
Eigen::MatrixXd measured_reference(const NoveltyCalibration& c) {
  return c.whitening.size() == 0 ? c.reference : Eigen::MatrixXd(c.reference * c.whitening);
}

// Cross-validated calibration scores (format 6): per fold, the whitening of the other folds' rows and each held-out
// row's score against its class's rows in the other folds, with the class's own k (group_k of the whole class,
// at most the rows left in the other folds). Stratified folds deal a class's members to consecutive folds, so a
// class of n >= 2 members keeps at least one member outside any fold.
void cross_validated_scores(NoveltyCalibration& c, const Eigen::MatrixXd& Xs, int n_groups, NoveltyDistance distance,
                            int folds, std::uint64_t seed) {
  const int n = static_cast<int>(Xs.rows());
  std::vector<std::size_t> members(static_cast<std::size_t>(n_groups), 0);
  for (int g : c.reference_class) ++members[static_cast<std::size_t>(g)];
  std::vector<double> d;
  for (const Split& fold : stratified_k_fold(c.reference_class, std::min(folds, n), seed)) {
    Eigen::MatrixXd rest(static_cast<Eigen::Index>(fold.train.size()), Xs.cols());
    std::vector<int> rest_class;
    for (std::size_t r = 0; r < fold.train.size(); ++r) {
      rest.row(static_cast<Eigen::Index>(r)) = Xs.row(fold.train[r]);
      rest_class.push_back(c.reference_class[static_cast<std::size_t>(fold.train[r])]);
    }
    const Eigen::MatrixXd W = distance == NoveltyDistance::Whitened ? within_class_whitening(rest, rest_class)
                                                                    : Eigen::MatrixXd::Identity(Xs.cols(), Xs.cols());
    const Eigen::MatrixXd M = rest * W;  // W symmetric: each row times W
    for (int i : fold.test) {
      const int g = c.reference_class[static_cast<std::size_t>(i)];
      if (members[static_cast<std::size_t>(g)] < 2) continue;  // one sample: no score (novelty_threshold borrows)
      const Eigen::RowVectorXd xi = Xs.row(i) * W;
      d.clear();
      for (std::size_t r = 0; r < rest_class.size(); ++r)
        if (rest_class[r] == g) d.push_back((M.row(static_cast<Eigen::Index>(r)) - xi).norm());
      if (d.empty()) throw InvalidInputError("training_data", "novelty calibration: a fold holds every member of a class");
      const int kg = std::min(group_k(c, members[static_cast<std::size_t>(g)]), static_cast<int>(d.size()));
      c.loo_scores[static_cast<std::size_t>(g)].push_back(mean_of_smallest(d, kg));
    }
  }
  for (auto& s : c.loo_scores) std::sort(s.begin(), s.end());
}

NoveltyCalibration calibrate_groups(const Eigen::MatrixXd& Xs, std::vector<int> groups, int n_groups, int k,
                                    double quantile, bool per_class, NoveltyDistance distance, int folds = 0,
                                    std::uint64_t seed = 0) {
  if (Xs.rows() < 2) throw InvalidInputError("training_data", "novelty calibration needs at least 2 training samples");
  NoveltyCalibration c;
  c.per_class = per_class;
  c.k = std::max(1, k);
  c.quantile = quantile;
  c.reference = Xs;
  c.reference_class = std::move(groups);
  if (distance == NoveltyDistance::Whitened) c.whitening = within_class_whitening(Xs, c.reference_class);
  c.loo_scores.resize(static_cast<std::size_t>(n_groups));
  if (folds > 0) {
    c.calibration_folds = std::min(folds, static_cast<int>(Xs.rows()));
    cross_validated_scores(c, Xs, n_groups, distance, c.calibration_folds, seed);
    return c;
  }
  const Eigen::MatrixXd M = measured_reference(c);
  std::vector<double> d;
  for (int g = 0; g < n_groups; ++g) {
    const auto rows = rows_of_group(c, g);
    if (rows.size() < 2) continue;  // one sample: no leave-one-out score (novelty_threshold borrows)
    const int kg = group_k(c, rows.size());
    for (Eigen::Index i : rows) {
      d.clear();
      for (Eigen::Index j : rows)
        if (j != i) d.push_back((M.row(i) - M.row(j)).norm());
      c.loo_scores[static_cast<std::size_t>(g)].push_back(mean_of_smallest(d, kg));
    }
    std::sort(c.loo_scores[static_cast<std::size_t>(g)].begin(), c.loo_scores[static_cast<std::size_t>(g)].end());
  }
  return c;
}

}  // namespace

Eigen::MatrixXd within_class_whitening(const Eigen::MatrixXd& Xs, const std::vector<int>& y) {
  const Eigen::Index n = Xs.rows(), p = Xs.cols();
  if (static_cast<Eigen::Index>(y.size()) != n || n < 1 || p < 1)
    throw InvalidInputError("training_data", "within-class whitening: " + std::to_string(y.size()) + " labels for " +
                                                 std::to_string(n) + " samples of " + std::to_string(p) + " features");
  // Residuals: each row minus its class mean (a class of one row contributes a zero residual).
  const int groups = *std::max_element(y.begin(), y.end()) + 1;
  Eigen::MatrixXd mean = Eigen::MatrixXd::Zero(groups, p);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(groups);
  for (Eigen::Index i = 0; i < n; ++i) {
    mean.row(y[static_cast<std::size_t>(i)]) += Xs.row(i);
    count(y[static_cast<std::size_t>(i)]) += 1;
  }
  for (int g = 0; g < groups; ++g)
    if (count(g) > 0) mean.row(g) /= count(g);
  Eigen::MatrixXd R(n, p);
  for (Eigen::Index i = 0; i < n; ++i) R.row(i) = Xs.row(i) - mean.row(y[static_cast<std::size_t>(i)]);
  // Ledoit & Wolf (2004), as scikit-learn's ledoit_wolf on centred data, then at least kMinShrinkage: S = R'R / n, target mu I with
  // mu = tr(S) / p, shrinkage s = min(b2, d2) / d2 with d2 = |S - mu I|^2 and b2 = (1/n^2) sum_i |r_i r_i' - S|^2
  // (Frobenius norms); sum_i |r_i r_i' - S|^2 = sum_i |r_i|^4 - n |S|^2.
  const double nn = static_cast<double>(n);
  const Eigen::MatrixXd S = R.transpose() * R / nn;
  const double mu = S.trace() / static_cast<double>(p);
  if (!(mu > 0)) return Eigen::MatrixXd::Identity(p, p);  // every class's members identical: nothing to whiten by
  const double d2 = (S - mu * Eigen::MatrixXd::Identity(p, p)).squaredNorm();
  const double b2 = std::max(0.0, (R.rowwise().squaredNorm().array().square().sum() - nn * S.squaredNorm()) / (nn * nn));
  // At least kMinShrinkage: Ledoit-Wolf minimises the error of C, but the distance uses C^(-1/2), whose
  // small-eigenvalue directions a few hundred samples under-estimate, so held-out members of known types look far:
  // measured (docs/benchmarks.md "Novelty"), Ledoit-Wolf alone flagged 2.4-3.1 % of held-out known members at the
  // 0.99 quantile, with the floor 1.3-2.4 %.
  const double s = std::max(kMinShrinkage, d2 > 0 ? std::min(b2, d2) / d2 : 1.0);
  const Eigen::MatrixXd C = (1 - s) * S + s * mu * Eigen::MatrixXd::Identity(p, p);
  // C^(-1/2) by the symmetric eigendecomposition; s > 0 or a full-rank S keeps the eigenvalues positive, and a
  // floor at 1e-12 of the largest guards the exact-fit case (s = 0 with a singular S).
  const linalg::SymmetricEigen eig = linalg::symmetric_eigen(C);
  if (!eig.converged)
    throw WishError(ErrorCategory::Internal, "internal",
                    "within-class whitening: the symmetric eigensolver did not converge on the " + std::to_string(p) +
                        " x " + std::to_string(p) + " shrunk covariance");
  const Eigen::VectorXd ev = eig.values.cwiseMax(1e-12 * eig.values.maxCoeff());
  return eig.vectors * ev.cwiseSqrt().cwiseInverse().asDiagonal() * eig.vectors.transpose();
}

NoveltyCalibration calibrate_novelty(const Eigen::MatrixXd& Xs, const std::vector<int>& y, int k, double quantile,
                                     NoveltyDistance distance, int folds, std::uint64_t seed) {
  if (static_cast<Eigen::Index>(y.size()) != Xs.rows())
    throw InvalidInputError("training_data", "novelty calibration: " + std::to_string(y.size()) + " labels for " +
                                                 std::to_string(Xs.rows()) + " samples");
  if (folds == 1 || folds < 0)
    throw InvalidInputError("invalid_parameter", "novelty calibration folds must be 0 (leave-one-out) or at least 2, got " +
                                                     std::to_string(folds));
  const int n_groups = y.empty() ? 0 : *std::max_element(y.begin(), y.end()) + 1;
  return calibrate_groups(Xs, y, n_groups, k, quantile, true, distance, folds, seed);
}

NoveltyCalibration calibrate_novelty_one_set(const Eigen::MatrixXd& Xs, int k, double quantile) {
  // The format-3 figure stored k already capped at n - 1.
  return calibrate_groups(Xs, std::vector<int>(static_cast<std::size_t>(Xs.rows()), 0), 1,
                          std::max(1, std::min<int>(k, static_cast<int>(Xs.rows()) - 1)), quantile, false,
                          NoveltyDistance::Euclidean);
}

double novelty_threshold(const NoveltyCalibration& c, double quantile, int group) {
  check_quantile(quantile);
  const auto& s = c.loo_scores.at(static_cast<std::size_t>(group));
  if (!s.empty()) return quantile_of(s, quantile);
  // A class of one training sample has no spread of its own: it takes the widest class's threshold.
  double widest = 0;
  for (const auto& other : c.loo_scores)
    if (!other.empty()) widest = std::max(widest, quantile_of(other, quantile));
  return widest;
}

double novelty_median(const NoveltyCalibration& c, int group) {
  const auto& s = c.loo_scores.at(static_cast<std::size_t>(group));
  if (!s.empty()) return quantile_of(s, 0.5);
  double widest = 0;  // a class of one training sample: the widest class's typical distance
  for (const auto& other : c.loo_scores)
    if (!other.empty()) widest = std::max(widest, quantile_of(other, 0.5));
  return widest;
}

double novelty_pooled_unit_threshold(const NoveltyCalibration& c, double quantile) {
  check_quantile(quantile);
  std::vector<double> units;
  for (const auto& s : c.loo_scores) {
    if (s.empty()) continue;
    const double m = quantile_of(s, 0.5);
    if (!(m > 0)) continue;  // identical members: no unit
    for (double v : s) units.push_back(v / m);
  }
  if (units.empty()) return 0;
  std::sort(units.begin(), units.end());
  return quantile_of(units, quantile);
}

NoveltyAssessment assess_novelty(const NoveltyCalibration& c, const Eigen::Ref<const Eigen::VectorXd>& x, double quantile,
                                 int predicted_group) {
  const double q = quantile > 0 ? quantile : c.quantile;
  check_quantile(q);
  const Eigen::MatrixXd M = measured_reference(c);
  const Eigen::VectorXd xm = c.whitening.size() == 0 ? Eigen::VectorXd(x) : Eigen::VectorXd(c.whitening * x);
  std::vector<NoveltyAssessment> per_group;
  std::vector<double> d, ratios;
  for (int g = 0; g < group_count(c); ++g) {
    NoveltyAssessment a;
    a.quantile = q;
    a.group = g;
    const auto rows = rows_of_group(c, g);
    if (rows.empty()) {
      ratios.push_back(std::numeric_limits<double>::infinity());  // no member: unlike it by any measure
      per_group.push_back(a);
      continue;
    }
    d.clear();
    for (Eigen::Index j : rows) d.push_back((M.row(j).transpose() - xm).norm());
    a.score = mean_of_smallest(d, group_k(c, rows.size()));
    const auto& s = c.loo_scores[static_cast<std::size_t>(g)];
    const auto at_least = s.end() - std::lower_bound(s.begin(), s.end(), a.score);
    a.p_value = (1.0 + static_cast<double>(at_least)) / (static_cast<double>(s.size()) + 1.0);
    a.threshold = novelty_threshold(c, a.quantile, g);
    a.novel = a.score > a.threshold;
    // Relative to the class's own spread; a zero threshold (identical training members) puts any distance at
    // infinity and a zero distance at 0.
    ratios.push_back(a.threshold > 0 ? a.score / a.threshold
                                     : (a.score > 0 ? std::numeric_limits<double>::infinity() : 0.0));
    per_group.push_back(a);
  }
  // The nearest class relative to its spread (ties: the larger p-value); a group without members is never it.
  int best = -1;
  for (int g = 0; g < group_count(c); ++g) {
    if (rows_of_group(c, g).empty()) continue;
    const auto gi = static_cast<std::size_t>(g);
    if (best < 0 || ratios[gi] < ratios[static_cast<std::size_t>(best)] ||
        (ratios[gi] == ratios[static_cast<std::size_t>(best)] && per_group[gi].p_value > per_group[static_cast<std::size_t>(best)].p_value))
      best = g;
  }
  if (c.rule == NoveltyRule::MedianScale) {
    // Per class the score over the class's median calibration score; the smallest decides against one pooled
    // threshold in those units (novelty.hpp). Reported threshold: that unit threshold times the class's median,
    // so novel == (score > threshold) still holds for the reported class.
    const double unit = novelty_pooled_unit_threshold(c, q);
    int nearest = -1;
    double nearest_units = 0;
    for (int g = 0; g < group_count(c); ++g) {
      if (rows_of_group(c, g).empty()) continue;
      const double m = novelty_median(c, g);
      const double s = per_group[static_cast<std::size_t>(g)].score;
      const double units = m > 0 ? s / m : (s > 0 ? std::numeric_limits<double>::infinity() : 0.0);
      if (nearest < 0 || units < nearest_units) {
        nearest = g;
        nearest_units = units;
      }
    }
    NoveltyAssessment out = per_group.at(static_cast<std::size_t>(std::max(nearest, 0)));
    out.threshold = unit * novelty_median(c, out.group);
    out.novel = out.score > out.threshold;
    // Why: per class the score over THIS rule's threshold of the class (unit x its median), so the reported class
    // has the smallest ratio and novel == (its ratio > 1), as for the other rules.
    for (int g = 0; g < group_count(c); ++g) {
      auto& r = ratios[static_cast<std::size_t>(g)];
      if (rows_of_group(c, g).empty()) continue;  // stays infinite
      const double t = unit * novelty_median(c, g), s = per_group[static_cast<std::size_t>(g)].score;
      r = t > 0 ? s / t : (s > 0 ? std::numeric_limits<double>::infinity() : 0.0);
    }
    out.class_ratios = std::move(ratios);
    return out;
  }
  if (c.rule == NoveltyRule::PredictedClass && predicted_group >= 0 && predicted_group < group_count(c) &&
      !rows_of_group(c, predicted_group).empty())
    best = predicted_group;
  NoveltyAssessment out = per_group.at(static_cast<std::size_t>(std::max(best, 0)));
  // NearestClass: novel iff the most alike class's score is above its threshold, i.e. above every class's.
  // PredictedClass: novel iff above the predicted class's threshold.
  out.class_ratios = std::move(ratios);
  return out;
}

void validate_novelty(const NoveltyCalibration& c, Eigen::Index n_features, int n_classes) {
  auto bad = [](const std::string& m) { throw InvalidInputError("model_invalid", "invalid model file: novelty: " + m); };
  const Eigen::Index n = c.reference.rows();
  if (n < 2) bad("needs at least 2 reference samples");
  if (c.reference.cols() != n_features)
    bad("reference samples have " + std::to_string(c.reference.cols()) + " features, the model " + std::to_string(n_features));
  if (static_cast<Eigen::Index>(c.reference_class.size()) != n)
    bad(std::to_string(c.reference_class.size()) + " reference classes for " + std::to_string(n) + " reference samples");
  const int groups = c.per_class ? n_classes : 1;
  if (static_cast<int>(c.loo_scores.size()) != groups)
    bad(std::to_string(c.loo_scores.size()) + " lists of leave-one-out scores for " + std::to_string(groups) +
        (c.per_class ? " classes" : " reference set"));
  if (c.k < 1 || (!c.per_class && c.k >= n)) bad("k = " + std::to_string(c.k) + " must be in 1.." + std::to_string(n - 1));
  if (!(c.quantile > 0 && c.quantile < 1)) bad("quantile must be between 0 and 1");
  std::vector<std::size_t> members(static_cast<std::size_t>(groups), 0);
  for (int g : c.reference_class) {
    if (g < 0 || g >= groups) bad("reference class " + std::to_string(g) + " is not one of the model's " + std::to_string(groups));
    ++members[static_cast<std::size_t>(g)];
  }
  bool any_scores = false;
  for (int g = 0; g < groups; ++g) {
    const auto& s = c.loo_scores[static_cast<std::size_t>(g)];
    const std::size_t expected = members[static_cast<std::size_t>(g)] >= 2 ? members[static_cast<std::size_t>(g)] : 0;
    if (s.size() != expected)
      bad(std::to_string(s.size()) + " leave-one-out scores for class " + std::to_string(g) + " of " +
          std::to_string(members[static_cast<std::size_t>(g)]) + " reference samples");
    if (!std::all_of(s.begin(), s.end(), [](double v) { return std::isfinite(v) && v >= 0; }))
      bad("non-finite or negative leave-one-out scores");
    if (!std::is_sorted(s.begin(), s.end())) bad("leave-one-out scores are not ascending");
    any_scores = any_scores || !s.empty();
  }
  if (!any_scores) bad("no class has 2 reference samples");
  if (!c.reference.allFinite()) bad("non-finite reference samples");
  if (c.whitening.size() != 0) {
    if (c.whitening.rows() != n_features || c.whitening.cols() != n_features)
      bad("whitening is " + std::to_string(c.whitening.rows()) + " x " + std::to_string(c.whitening.cols()) + ", the model has " +
          std::to_string(n_features) + " features");
    if (!c.whitening.allFinite()) bad("non-finite whitening");
    if ((c.whitening - c.whitening.transpose()).norm() > 1e-9 * c.whitening.norm()) bad("whitening is not symmetric");
    if (!c.per_class) bad("whitening without per-class calibration");
  }
  if (c.calibration_folds < 0 || c.calibration_folds == 1 || c.calibration_folds > n)
    bad("calibration_folds = " + std::to_string(c.calibration_folds) + " must be 0 (leave-one-out) or in 2.." + std::to_string(n));
  if (c.calibration_folds > 0 && !c.per_class) bad("cross-validated calibration without per-class calibration");
  if (c.rule != NoveltyRule::NearestClass && !c.per_class) bad("the predicted-class rule without per-class calibration");
}

}  // namespace wish
