#pragma once
// "None of the known types" (issue 25): how unlike the training set a sample is, in the model's own standardised
// feature space (after the feature pipeline and the z-score scaler, where the SVM works).
//  * score: the mean Euclidean distance from the sample to its k nearest training samples (k = 5, or n - 1 when
//    the training set is smaller);
//  * calibration (at training time, stored in the model file): every training sample's leave-one-out score (its k
//    nearest *other* training samples), sorted — the distribution of scores of samples of the known types;
//  * p_value = (1 + #{leave-one-out scores >= score}) / (n + 1): the conformal p-value of the sample against the
//    training set (small: unlike everything seen in training);
//  * threshold: the q-quantile of the leave-one-out scores (linear interpolation, numpy's default), q = 0.99 unless
//    the caller says otherwise (`wish predict --novelty-quantile`, `wish serve --novelty-quantile`);
//    novel = score > threshold. About 1 - q of new samples of the known types are flagged by construction.
// A k-nearest-neighbour distance rather than the SVM's probabilities: a one-vs-one SVM extrapolates a confident
// label far from all its training data, so its probabilities cannot say "none of these".

#include <vector>

#include <Eigen/Core>

namespace wish {

struct NoveltyCalibration {
  int k = 5;
  Eigen::MatrixXd reference;       // standardised training samples, one per row
  std::vector<double> loo_scores;  // ascending, one per reference row
  double quantile = 0.99;          // the model's default threshold quantile
};

struct NoveltyAssessment {
  double score = 0;      // mean distance to the k nearest training samples
  double p_value = 1;    // conformal p-value against the leave-one-out scores
  double threshold = 0;  // the quantile's leave-one-out score
  double quantile = 0;   // the quantile used
  bool novel = false;    // score > threshold
};

// Xs: the standardised training samples the SVM was fitted on (at least 2 rows). Throws
// InvalidInputError("training_data") when there are fewer than 2 samples.
NoveltyCalibration calibrate_novelty(const Eigen::MatrixXd& Xs, int k = 5, double quantile = 0.99);

// The q-quantile (0 < q < 1) of the leave-one-out scores. Throws InvalidInputError("invalid_parameter") otherwise.
double novelty_threshold(const NoveltyCalibration& c, double quantile);

// x: one standardised sample (the reference's column count). quantile <= 0: the calibration's own quantile.
NoveltyAssessment assess_novelty(const NoveltyCalibration& c, const Eigen::Ref<const Eigen::VectorXd>& x,
                                 double quantile = 0);

// Checks sizes, k, finiteness and order; throws InvalidInputError("model_invalid") naming what is wrong.
void validate_novelty(const NoveltyCalibration& c, Eigen::Index n_features);

}  // namespace wish
