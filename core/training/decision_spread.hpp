#pragma once
// Whether a fitted SVM decides by its kernel expansion or only by its offset (issue 37 follow-up, measured
// 2026-12-06 in docs/accuracy.md "Grid cells decided by the offset").
//
// A pairwise C-SVM's decision value is f(x) = sum_i alpha_i y_i K(x_i, x) - rho (libsvm; > 0 favours the pair's
// first class). When the fit has a free support vector of each class (0 < alpha < C), those sit exactly on the
// margin, f = +1 and f = -1, so f spreads over at least 2 across the pair's own training rows. At a tiny C (or a
// gamma so small that K is nearly constant) every alpha sits at its bound C, the expansion is nearly the same for
// every row, and f is nearly constant: the pair's answer is decided by rho alone, i.e. by the class balance of the
// rows it was fitted on. Such a cell can score well on balanced validation splits and then, refitted on all rows
// with their real imbalance, put every sample into the larger class (measured: demo48, C = 1e-2 gamma = 1e-8,
// validation 0.812, training accuracy of the final model 0.368). The grid search therefore never chooses a cell
// whose fits are mostly offset-decided while another cell is available (grid_search.hpp).
//
// Spread of one fit: the smallest, over class pairs (i, j), of max - min of the pair's decision value over the
// training rows of classes i and j. Narrow: below kMarginSpread (= 2, the distance between the two margins).
// Why the smallest pair, not "every pair narrow": one offset-decided pair already collapses its two classes into
// one in an unbalanced refit; measured by nested CV over 9 sets x 3 feature families (docs/accuracy.md), the
// smallest pair's rule gives a mean of 0.871, every-pair 0.860, no check 0.824.

#include <functional>
#include <vector>

namespace wish {

inline constexpr double kMarginSpread = 2.0;

class DecisionSpread {
 public:
  // model_labels: the label of each internal class of the fit, in libsvm's order (pairs (a < b) over this order).
  explicit DecisionSpread(const std::vector<int>& model_labels);
  // One training row of class `label` with its k(k-1)/2 pairwise decision values (libsvm's svm_predict_values order).
  void add(int label, const std::vector<double>& decision);
  // Minimum over pairs of (max - min); +infinity when a pair saw no rows (nothing to judge), 0 for a constant pair.
  double spread() const;
  bool narrow() const { return spread() < kMarginSpread; }
  // Every pair already spans at least kMarginSpread: no further row can make the fit narrow.
  bool settled() const { return spread() >= kMarginSpread; }

 private:
  std::vector<int> labels_;
  std::vector<double> low_, high_;  // per pair
};

// The spread of one fit over its training rows `rows` (labels[i]: the class of rows[i]), `decision(row)` giving the
// row's pairwise decision values. The rows are visited round-robin over their classes and the scan stops once the
// spread is settled, so a fit that spans the margin costs a few predictions, not one per training row (measured:
// predicting every training row made `wish train` on 3,000 rows 1.47x slower). Exact when below kMarginSpread; at
// least kMarginSpread otherwise.
double fit_decision_spread(const std::vector<int>& model_labels, const std::vector<int>& rows,
                           const std::vector<int>& labels, const std::function<std::vector<double>(int row)>& decision);

// A cell is offset-decided when more than half of its split fits are narrow.
inline bool offset_decided(int narrow_fits, int fits) { return 2 * narrow_fits > fits; }

}  // namespace wish
