#pragma once
// RBF C-SVM on libsvm 3.24 (the engine behind scikit-learn's SVC; paper §6, docs/design/classification.md), wrapped so that
// a model owns everything libsvm points into. libsvm traps handled here:
//  * a freshly trained svm_model points into the training nodes: we copy the trained model into SvmModelData
//    (plain owned arrays) right away and free libsvm's struct; prediction runs on an svm_model *view* whose
//    pointers all point into this object's own storage;
//  * svm_save_model / svm_load_model call the process-global setlocale: never used, the model file is our JSON;
//  * training with probability estimates calls rand(): srand(seed) + svm_train run under one global mutex, so a
//    seed gives the same model (including Platt's probA/probB) whatever other threads do;
//  * libsvm prints to stdout: its messages never reach the terminal; the iteration-cap warnings of a fit are counted
//    (libsvm_messages.hpp) and returned to the caller.
// Class labels are 0..k-1; samples are stably sorted by label before training so that libsvm's class order
// equals 0..k-1 (as in scikit-learn, whose libsvm sorts labels), which makes vote ties and decision-value
// signs match scikit-learn's SVC.

#include <memory>
#include <vector>

#include <Eigen/Core>

namespace wish {

struct SvmParams {
  double C = 1.0;
  double gamma = 1.0;          // K(x, y) = exp(-gamma |x - y|^2)
  bool probability = true;     // fit Platt's sigmoid (libsvm's internal 5-fold CV)
  double tolerance = 1e-3;     // libsvm eps, scikit-learn tol
  double cache_mb = 100;
  bool shrinking = true;
};

// A trained model as owned plain data (what the model file stores).
struct SvmModelData {
  double C = 0, gamma = 0;
  int n_features = 0;
  int n_classes = 0;
  std::vector<int> labels;          // libsvm label of each internal class (a permutation of 0..k-1)
  std::vector<int> n_sv;            // support vectors per internal class, in order; sums to #SV
  Eigen::MatrixXd support_vectors;  // #SV by n_features (dense)
  Eigen::MatrixXd sv_coef;          // (k-1) by #SV
  std::vector<double> rho;          // k(k-1)/2
  std::vector<double> prob_a, prob_b;  // k(k-1)/2 each, or empty when trained without probabilities
};

struct SvmOutput {
  int label = -1;                   // one-vs-one vote winner (libsvm svm_predict, scikit-learn SVC.predict)
  std::vector<double> votes;        // per class label 0..k-1
  std::vector<double> decision;     // k(k-1)/2 pairwise values, pair (i<j) in label order; > 0 favours i
  std::vector<double> probability;  // per class label 0..k-1; empty without a probability model
};

class SvmEngine {
 public:
  // X: one sample per row; y: labels in 0..k-1 (every label present, k >= 2). Deterministic given `seed`.
  // iteration_cap_warnings (optional): how many of the fit's pairwise solvers (including those of the Platt
  // calibration's internal cross-validation) stopped at libsvm's iteration cap, i.e. did not converge.
  static SvmEngine train(const Eigen::MatrixXd& X, const std::vector<int>& y, const SvmParams& params,
                         unsigned seed, int* iteration_cap_warnings = nullptr);
  // Validates sizes and finiteness; throws InvalidInputError("model_invalid") on inconsistency.
  explicit SvmEngine(SvmModelData data);
  SvmEngine(SvmEngine&&) noexcept;
  SvmEngine& operator=(SvmEngine&&) noexcept;
  ~SvmEngine();

  const SvmModelData& data() const;
  bool has_probability() const;
  // Thread-safe (libsvm prediction only reads the model). x.size() must equal n_features.
  SvmOutput predict(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  int predict_label(const Eigen::Ref<const Eigen::VectorXd>& x) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace wish
