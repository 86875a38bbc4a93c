#pragma once
// "None of the known types" (issue 25): how unlike every known class a sample is, in the model's own standardised
// feature space (after the feature pipeline and the z-score scaler, where the SVM works).
//
// Per class (model format 4; format 5 measures the distance in a whitened space, see below):
//  * score of class c: the mean distance from the sample to its k nearest members of class c among the
//    training samples (k = 3 by default, or n_c - 1 for a class of fewer samples);
//  * calibration (at training time, stored in the model file): every training sample's leave-one-out score against
//    its OWN class (its k nearest other members; or cross-validated, below), sorted per class — how far a new
//    member of c lies from c's training members;
//  * threshold of class c: the q-quantile of c's leave-one-out scores (linear interpolation, numpy's default),
//    q = 0.99 unless the caller says otherwise (`wish predict --novelty-quantile`, `wish serve --novelty-quantile`);
//  * novel: the sample's score is above the threshold of EVERY class — it is unlike each known type, measured on
//    that type's own spread. About 1 - q of a class's new members exceed its own threshold by construction, and
//    such a sample is flagged only if it is also beyond every other class's, so the false-flag rate stays at or
//    below about 1 - q.
//  * reported: the class the sample is most like relative to its spread (the smallest score / threshold): its score,
//    its threshold, and its conformal p-value (1 + #{its leave-one-out scores >= score}) / (n_c + 1) — which is the
//    largest over the classes up to ties. novel == (score > threshold) for that class.
// This is a label-conditional ("Mondrian") conformal test with a k-NN nonconformity score (Vovk, Gammerman &
// Shafer, Algorithmic Learning in a Random World, 2005, ch. 4; Laxhammar & Falkman 2015 for k-NN conformal anomaly
// detection): a sample is novel when the conformal prediction set at level q is empty. Per class rather than one
// distance to the whole training set, because known types differ in spread: a sample between two tight classes is
// far from both in their own units, but not far from the training set as a whole (measured, leave-one-class-out,
// docs/benchmarks.md: 360 demo descriptors 174 -> 250 left-out members flagged, 360 UroCell ones 80 -> 107, known
// members flagged <= 0.6 % either way). It does not reach the 90 %: see docs/benchmarks.md for why.
// The distance (format 5, the default): |W (a - b)| with W = C^(-1/2), C the covariance of the training samples
// about their own class means pooled over the classes, shrunk towards a multiple of the identity by the Ledoit-Wolf
// estimate (Ledoit & Wolf, J. Multivariate Anal. 88, 2004), at least by half — a Mahalanobis distance by the within-class spread, as
// in Lee et al. (NeurIPS 2018) for out-of-distribution detection, here inside the k-NN conformal test. Why: the
// directions in which members of one type vary (above all size: xi(l) scales as length^2, so log xi shifts all
// together) dominate the standardised features, and a Euclidean k-NN radius calibrated along them hides a new type
// that differs in the directions a type hardly varies in. Measured in docs/benchmarks.md "Novelty".
// A k-nearest-neighbour distance rather than the SVM's probabilities: a one-vs-one SVM extrapolates a confident
// label far from all its training data, so its probabilities cannot say "none of these".
//
// Calibration scores, leave-one-out (formats 3-5, the default) or cross-validated (format 6, an option:
// TrainOptions::novelty_folds, `wish train --novelty-folds 10`). Leave-one-out scores keep the sample inside the
// whitening it is measured in and score it against every other member of its class, so they are a little smaller
// than a new member's and the q threshold flags more than 1 - q of new known members: at q = 0.99, measured
// (docs/benchmarks.md "Novelty", numpy, 5 splits) 2.2 % of held-out known UroCell members (raw marching cubes,
// xi + global), 3.1 % on the meshed UroCell set, 1.3 % on the demo set. Cross-validated scores score each training
// sample as a new one: against its class's members in the other folds, whitened by the other folds only (10
// stratified folds, deterministic for the seed): 1.3 %, 2.5 %, 1.1 % on the same splits. At EQUAL false-flag rates
// the two flag about the same share of a left-out type (within 1.5 points; 2.6-4.1 points fewer cross-validated on
// the meshed set): the choice moves the operating point, it does not make the figure see more. Leave-one-out stays
// the default for that reason and because it flags more of a new type at the same quantile (the generated set of
// classify_novelty_test: 96 % against 87 % of a left-out type, 2 % of known members either way). With few training
// samples per class leave-one-out scores fail: on the bundled model's demo set (about 10 per class) they flagged
// 9 of 72 held-out known members, cross-validated ones 3 of 72, so that model is calibrated cross-validated.
// Model format 4 files (no whitening) load and compute their Euclidean figure.
// Model format 3 files carry the first figure (one reference set: every training sample, one list of leave-one-out
// scores). They load as one group and compute exactly what they computed when written.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/common/enum_names.hpp"

namespace wish {

// Which class's threshold decides (issue 38, measured in docs/benchmarks.md "Novelty, issue 38").
enum class NoveltyRule {
  NearestClass,    // formats 3-6: novel when the score is above EVERY class's threshold; reported: the class the
                   // sample is most like relative to its spread (one wide class hides every sample near it)
  PredictedClass,  // format 7: novel when the score against the class the SVM predicts is above that class's
                   // threshold; reported: that class
  MedianScale,     // format 8 (issue 38, second pass): per class the score in units of the class's TYPICAL
                   // distance (the median of its calibration scores, not its tail quantile); reported: the class
                   // with the smallest such ratio; novel when that ratio is above the q-quantile of every class's
                   // calibration scores in the same units, pooled over the classes (one threshold in units, so a
                   // class whose calibration tail holds a few stragglers does not hide the samples near it).
                   // Computed from the stored calibration scores alone. Measured (docs/accuracy.md "Issue 38"):
                   // at 2 % of known flagged it detects 6-9 points more of a left-out class than NearestClass on
                   // each of three sets, at 5 % equal or more; AUROC 0.4-2 points lower on two of them.
};
inline constexpr EnumNames<NoveltyRule, 3> kNoveltyRuleNames{{{
    {NoveltyRule::NearestClass, "nearest_class"},
    {NoveltyRule::PredictedClass, "predicted_class"},
    {NoveltyRule::MedianScale, "median_scale"}}}};
const char* to_string(NoveltyRule rule);  // kNoveltyRuleNames

// How distances are measured in the standardised feature space.
enum class NoveltyDistance {
  Euclidean,  // formats 3 and 4
  Whitened,   // format 5: Mahalanobis by the pooled within-class covariance, Ledoit-Wolf shrunk
};

struct NoveltyCalibration {
  // false: the format-3 figure (all reference rows one group); true: per class (format 4).
  bool per_class = true;
  int k = 3;
  double quantile = 0.99;                         // the model's default threshold quantile
  Eigen::MatrixXd reference;                      // standardised training samples, one per row
  std::vector<int> reference_class;               // per row, its group: the model's class index (0 for all rows when !per_class)
  std::vector<std::vector<double>> loo_scores;    // per group, ascending, one per row of the group
  // Empty: Euclidean distances (formats 3 and 4). Otherwise W (features x features, symmetric) and every distance
  // is |W (a - b)|: the reference rows stay standardised, W is applied to both sides.
  Eigen::MatrixXd whitening;
  // How loo_scores were made: 0 leave-one-out (formats 3-5); >= 2 cross-validated with that many stratified folds
  // (format 6; the name loo_scores stays, it is the file's key). Prediction computes the same either way.
  int calibration_folds = 0;
  NoveltyRule rule = NoveltyRule::NearestClass;  // format 7 stores predicted_class, format 8 median_scale
};

struct NoveltyAssessment {
  double score = 0;      // mean distance to the k nearest training samples of the reported class
  double p_value = 1;    // conformal p-value against that class's leave-one-out scores
  double threshold = 0;  // that class's leave-one-out score at the quantile
  double quantile = 0;   // the quantile used
  bool novel = false;    // above every class's threshold (== score > threshold)
  int group = 0;         // the reported class (model class index; 0 when !per_class); last, so that brace
                         // initialisers of the first five fields keep their meaning
  // Why (issue 38 item 3): per group (model class order), the sample's score divided by that class's threshold —
  // its distance in units of the class's own calibration spread (1 = at the class's quantile; novel when every
  // entry is above 1). The reported group has the smallest. MedianScale: over that rule's threshold of each class
  // (the pooled unit threshold times the class's median), so novel iff the reported class's ratio is above 1.
  std::vector<double> class_ratios;
};

// Xs: the standardised training samples the SVM was fitted on (at least 2 rows), y: their class indices
// (0..classes-1, every class present). folds: 0 leave-one-out calibration scores (formats 3-5), >= 2 that many
// stratified cross-validation folds (capped at the number of samples; seed: their shuffle, splits.hpp). Throws
// InvalidInputError("training_data") when there are fewer than 2 samples, ("invalid_parameter") for folds 1 or < 0.
inline constexpr int kNoveltyFolds = 10;  // the cross-validated option's folds (`wish train --novelty-folds`)
NoveltyCalibration calibrate_novelty(const Eigen::MatrixXd& Xs, const std::vector<int>& y, int k = 3,
                                     double quantile = 0.99, NoveltyDistance distance = NoveltyDistance::Whitened,
                                     int folds = 0, std::uint64_t seed = 42);
// The format-3 figure (one group): kept for reading older model files and for the measurement that compares them.
NoveltyCalibration calibrate_novelty_one_set(const Eigen::MatrixXd& Xs, int k = 5, double quantile = 0.99);

// W = C^(-1/2) (symmetric), C the covariance of the rows of Xs about their class means (y: class indices >= 0),
// shrunk towards mu I (mu its mean eigenvalue): C = (1 - s) S + s mu I with s the Ledoit-Wolf estimate of the
// shrinkage, at least kMinShrinkage (novelty.cpp says why); the identity when every class's members coincide.
// Throws InvalidInputError("training_data") on mismatched sizes.
inline constexpr double kMinShrinkage = 0.5;
Eigen::MatrixXd within_class_whitening(const Eigen::MatrixXd& Xs, const std::vector<int>& y);

// The q-quantile (0 < q < 1) of one group's leave-one-out scores. Throws InvalidInputError("invalid_parameter")
// otherwise. A group of one sample has no leave-one-out score: it takes the largest threshold of the other groups.
double novelty_threshold(const NoveltyCalibration& c, double quantile, int group = 0);

// x: one standardised sample (the reference's column count). quantile <= 0: the calibration's own quantile.
// predicted_group: the class the classifier predicts (model class index); the PredictedClass rule reports and
// decides by it, and falls back to the nearest class when it is out of range (-1: not known).
NoveltyAssessment assess_novelty(const NoveltyCalibration& c, const Eigen::Ref<const Eigen::VectorXd>& x,
                                 double quantile = 0, int predicted_group = -1);

// MedianScale rule: the median of group g's calibration scores (a group without scores takes the largest median
// of the others), and the pooled threshold in those units: the q-quantile (0 < q < 1) of every group's calibration
// scores divided by its group's median (groups of median 0 left out; 0 when no group has a positive median).
double novelty_median(const NoveltyCalibration& c, int group);
double novelty_pooled_unit_threshold(const NoveltyCalibration& c, double quantile);

// Checks sizes, k, groups, finiteness and order; throws InvalidInputError("model_invalid") naming what is wrong.
void validate_novelty(const NoveltyCalibration& c, Eigen::Index n_features, int n_classes);

}  // namespace wish
