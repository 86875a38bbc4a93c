#include "core/training/precomputed_kernel.hpp"

#include <svm.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "core/classify/libsvm_messages.hpp"
#include "core/common/errors.hpp"
#include "core/training/decision_spread.hpp"

namespace wish {

Eigen::MatrixXd pairwise_squared_distances(const Eigen::MatrixXd& X) {
  const Eigen::Index n = X.rows();
  const Eigen::MatrixXd T = X.transpose();  // column access per sample
  Eigen::MatrixXd D(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    D(j, j) = 0;
    for (Eigen::Index i = j + 1; i < n; ++i) D(i, j) = D(j, i) = (T.col(i) - T.col(j)).squaredNorm();
  }
  return D;
}

struct PrecomputedKernel::Impl {
  int n = 0;
  std::vector<svm_node> nodes;  // row i at i * (n + 2)
  const svm_node* row(int i) const { return nodes.data() + static_cast<std::size_t>(i) * (n + 2); }
  svm_node* row(int i) { return nodes.data() + static_cast<std::size_t>(i) * (n + 2); }
};

PrecomputedKernel::PrecomputedKernel(PrecomputedKernel&&) noexcept = default;
PrecomputedKernel::~PrecomputedKernel() = default;

PrecomputedKernel::PrecomputedKernel(const Eigen::MatrixXd& D, double gamma) : impl_(std::make_unique<Impl>()) {
  const int n = static_cast<int>(D.rows());
  impl_->n = n;
  impl_->nodes.resize(static_cast<std::size_t>(n) * (n + 2));
  for (int i = 0; i < n; ++i) {
    svm_node* r = impl_->row(i);
    r[0] = {0, static_cast<double>(i + 1)};
    for (int j = 0; j < n; ++j) r[j + 1] = {j + 1, std::exp(-gamma * D(i, j))};
    r[n + 1] = {-1, 0.0};
  }
}

PrecomputedKernel::FitScore PrecomputedKernel::fit_and_score(const std::vector<int>& train, const std::vector<int>& test,
                                                             const std::vector<int>& y, const SvmParams& params) const {
  std::vector<int> order = train;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return y[a] < y[b]; });
  std::vector<svm_node*> xs;
  std::vector<double> targets;
  for (int i : order) {
    xs.push_back(const_cast<svm_node*>(impl_->row(i)));  // libsvm's problem type is non-const; it only reads
    targets.push_back(y[i]);
  }
  svm_problem problem{static_cast<int>(order.size()), targets.data(), xs.data()};
  svm_parameter param{};
  param.svm_type = C_SVC;
  param.kernel_type = PRECOMPUTED;
  param.C = params.C;
  param.cache_size = params.cache_mb;
  param.eps = params.tolerance;
  param.shrinking = params.shrinking ? 1 : 0;
  param.probability = 0;  // accuracy needs votes only; no rand(), so fits run concurrently
  if (const char* error = svm_check_parameter(&problem, &param))
    throw InvalidInputError("training_parameters", std::string("libsvm refused the parameters: ") + error);
  FitScore score;
  svm_model* model = nullptr;
  {
    IterationCapCounter cap;
    model = svm_train(&problem, &param);
    score.iteration_cap_warnings = cap.warnings();
  }
  for (int i : test) score.correct += static_cast<int>(svm_predict(model, impl_->row(i))) == y[i];
  std::vector<int> order_labels;
  for (int i : order) order_labels.push_back(y[i]);
  std::vector<double> decision(static_cast<std::size_t>(model->nr_class) * (model->nr_class - 1) / 2);
  score.decision_spread = fit_decision_spread(std::vector<int>(model->label, model->label + model->nr_class), order,
                                              order_labels, [&](int row) {
                                                svm_predict_values(model, impl_->row(row), decision.data());
                                                return decision;
                                              });
  svm_free_and_destroy_model(&model);  // free_sv == 0: the nodes are ours
  return score;
}

}  // namespace wish
