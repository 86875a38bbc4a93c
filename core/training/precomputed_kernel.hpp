#pragma once
// One RBF kernel matrix, computed once and handed to libsvm as a precomputed kernel (issue 25): in a grid search the
// kernel K(i, j) = exp(-gamma |x_i - x_j|^2) depends on gamma only, so one matrix over all samples serves every C and
// every split of a gamma row, instead of libsvm re-evaluating exponentials for each of the rows x splits fits.
// libsvm's PRECOMPUTED input (README of libsvm): sample i is the node list {0: serial}, {1: K(i, 0)}, ...,
// {n: K(i, n-1)}, {-1}; libsvm looks the kernel up as x[serial of y].value. The serial numbers here are global (the
// sample's row in X, 1-based), so any subset of rows is a valid training problem over the same node lists, and a
// held-out row predicts against a model trained on other rows without copying anything.
// Used for model selection only: the model a user gets is retrained as a plain RBF SVM (svm_engine.hpp), so the
// model file and the predict path do not depend on the samples it was selected on.

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/classify/svm_engine.hpp"

namespace wish {

// |x_i - x_j|^2 for all rows of X (sums of squared differences, as libsvm's RBF prediction computes them).
Eigen::MatrixXd pairwise_squared_distances(const Eigen::MatrixXd& X);

class PrecomputedKernel {
 public:
  // exp(-gamma D), D from pairwise_squared_distances. Memory: n (n + 2) libsvm nodes of 16 bytes.
  PrecomputedKernel(const Eigen::MatrixXd& squared_distances, double gamma);
  PrecomputedKernel(PrecomputedKernel&&) noexcept;
  ~PrecomputedKernel();

  struct FitScore {
    int correct = 0;              // test rows predicted right (libsvm's one-vs-one vote, as svm_predict)
    int iteration_cap_warnings = 0;  // pairwise solvers of this fit that stopped at libsvm's iteration cap
    // The fit's decision spread over its own training rows (decision_spread.hpp: fit_decision_spread, exact below
    // kMarginSpread, at least kMarginSpread otherwise): below it the fit is decided by its offset, not its kernel.
    double decision_spread = 0;
  };
  // C-SVC (params.C, tolerance, cache, shrinking; no probabilities) on rows `train` with labels y[row] (0..k-1),
  // scored on rows `test`, with the fit's decision spread over rows `train`. Rows are stably ordered by label before
  // training, as SvmEngine::train does, so the vote order and ties are the same as a plain RBF fit's. Thread-safe: concurrent fits only read the nodes.
  FitScore fit_and_score(const std::vector<int>& train, const std::vector<int>& test, const std::vector<int>& y,
                         const SvmParams& params) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace wish
