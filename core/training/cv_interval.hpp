#pragma once
// The 95 % interval a cross-validated accuracy is reported with (issue 40: above a size the nested CV runs fewer
// folds, so its uncertainty is stated, not implied). Fold scores are not independent: every two training sets
// share most of their samples, so the plain standard error s / sqrt(J) is too small (Bengio & Grandvalet 2004: no
// unbiased estimator of k-fold CV's variance exists). We use the corrected resampled t interval of Nadeau & Bengio
// (2003, "Inference for the generalization error"), in its repeated k-fold form (Bouckaert & Frank 2004):
//     mean +- t(0.975, J - 1) * sqrt((1 / J + n_test / n_train) * s^2),
// J = the fold scores (repeats x folds), s^2 their sample variance (J - 1 in the denominator), n_test / n_train =
// 1 / (k - 1) for k folds. A heuristic that errs on the wide side, clipped to [0, 1]; none for fewer than 2 scores.

#include <optional>
#include <vector>

namespace wish {

struct Interval {
  double low = 0, high = 0;
};

// scores: accuracies of the outer folds (all repeats); test_over_train: n_test / n_train of one fold.
std::optional<Interval> cv_interval(const std::vector<double>& scores, double test_over_train);

// The p-quantile (0 < p < 1) of Student's t distribution with df >= 1 degrees of freedom (bisection on its CDF, the
// regularised incomplete beta function by Lentz's continued fraction; |error| < 1e-10).
double student_t_quantile(double p, int df);

}  // namespace wish
