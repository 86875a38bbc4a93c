#include "core/classify/svm_engine.hpp"

#include <svm.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <numeric>
#include <string>

#include "core/classify/libsvm_messages.hpp"
#include "core/common/errors.hpp"

namespace wish {
namespace {

// Serialises srand()+svm_train with probabilities: rand() is process-global state.
std::mutex& rand_mutex() {
  static std::mutex m;
  return m;
}

[[noreturn]] void invalid_svm(const std::string& message) { throw InvalidInputError("model_invalid", message); }

void append_dense(std::vector<svm_node>& nodes, const double* x, int n) {
  for (int j = 0; j < n; ++j) nodes.push_back({j + 1, x[j]});
  nodes.push_back({-1, 0.0});
}

}  // namespace

struct SvmEngine::Impl {
  SvmModelData data;
  // The view libsvm predicts with; every pointer points into the members below.
  std::vector<svm_node> sv_nodes;
  std::vector<svm_node*> sv_ptrs;
  std::vector<double*> coef_ptrs;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> coef_rows;
  std::vector<double> rho, prob_a, prob_b;
  std::vector<int> labels, n_sv;
  svm_model view{};

  void build_view() {
    const auto& d = data;
    const int l = static_cast<int>(d.support_vectors.rows());
    sv_nodes.clear();
    sv_nodes.reserve(static_cast<std::size_t>(l) * (d.n_features + 1));
    for (int i = 0; i < l; ++i) {
      const Eigen::VectorXd row = d.support_vectors.row(i).transpose();
      append_dense(sv_nodes, row.data(), d.n_features);
    }
    sv_ptrs.resize(l);
    for (int i = 0; i < l; ++i) sv_ptrs[i] = sv_nodes.data() + static_cast<std::size_t>(i) * (d.n_features + 1);
    coef_rows = d.sv_coef;
    coef_ptrs.resize(coef_rows.rows());
    for (Eigen::Index r = 0; r < coef_rows.rows(); ++r) coef_ptrs[r] = coef_rows.row(r).data();
    rho = d.rho;
    prob_a = d.prob_a;
    prob_b = d.prob_b;
    labels = d.labels;
    n_sv = d.n_sv;

    view = svm_model{};
    view.param.svm_type = C_SVC;
    view.param.kernel_type = RBF;
    view.param.gamma = d.gamma;
    view.param.C = d.C;
    view.param.probability = prob_a.empty() ? 0 : 1;
    view.nr_class = d.n_classes;
    view.l = l;
    view.SV = sv_ptrs.data();
    view.sv_coef = coef_ptrs.data();
    view.rho = rho.data();
    view.probA = prob_a.empty() ? nullptr : prob_a.data();
    view.probB = prob_b.empty() ? nullptr : prob_b.data();
    view.sv_indices = nullptr;
    view.label = labels.data();
    view.nSV = n_sv.data();
    view.free_sv = 1;  // never freed by libsvm anyway: we never pass the view to svm_free_*
  }
};

SvmEngine::SvmEngine(SvmEngine&&) noexcept = default;
SvmEngine& SvmEngine::operator=(SvmEngine&&) noexcept = default;
SvmEngine::~SvmEngine() = default;

SvmEngine::SvmEngine(SvmModelData data) : impl_(std::make_unique<Impl>()) {
  const int k = data.n_classes;
  const Eigen::Index l = data.support_vectors.rows();
  const std::size_t pairs = static_cast<std::size_t>(k) * (k - 1) / 2;
  if (k < 2) invalid_svm("the SVM has " + std::to_string(k) + " classes; at least 2 are needed");
  if (data.n_features < 1) invalid_svm("the SVM has no features");
  if (!(data.gamma > 0) || !(data.C > 0)) invalid_svm("the SVM's C and gamma must be positive");
  if (data.support_vectors.cols() != data.n_features)
    invalid_svm("support vectors have " + std::to_string(data.support_vectors.cols()) + " columns, the SVM expects " +
            std::to_string(data.n_features));
  if (static_cast<int>(data.labels.size()) != k || static_cast<int>(data.n_sv.size()) != k)
    invalid_svm("the SVM's labels / n_sv do not have one entry per class (" + std::to_string(k) + ")");
  std::vector<int> sorted = data.labels;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < k; ++i)
    if (sorted[i] != i) invalid_svm("the SVM's labels are not a permutation of 0.." + std::to_string(k - 1));
  if (std::accumulate(data.n_sv.begin(), data.n_sv.end(), Eigen::Index{0}) != l ||
      std::any_of(data.n_sv.begin(), data.n_sv.end(), [](int n) { return n < 0; }))
    invalid_svm("n_sv does not add up to the " + std::to_string(l) + " support vectors");
  if (data.sv_coef.rows() != k - 1 || data.sv_coef.cols() != l)
    invalid_svm("sv_coef is " + std::to_string(data.sv_coef.rows()) + " x " + std::to_string(data.sv_coef.cols()) +
            ", expected " + std::to_string(k - 1) + " x " + std::to_string(l));
  if (data.rho.size() != pairs) invalid_svm("rho has " + std::to_string(data.rho.size()) + " entries, expected " + std::to_string(pairs));
  if (!(data.prob_a.empty() && data.prob_b.empty()) && (data.prob_a.size() != pairs || data.prob_b.size() != pairs))
    invalid_svm("probA/probB must have " + std::to_string(pairs) + " entries each");
  auto finite = [](const auto& v) { return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }); };
  if (!data.support_vectors.allFinite() || !data.sv_coef.allFinite() || !finite(data.rho) || !finite(data.prob_a) ||
      !finite(data.prob_b))
    invalid_svm("the SVM contains non-finite numbers");
  impl_->data = std::move(data);
  impl_->build_view();
}

const SvmModelData& SvmEngine::data() const { return impl_->data; }
bool SvmEngine::has_probability() const { return !impl_->data.prob_a.empty(); }

SvmEngine SvmEngine::train(const Eigen::MatrixXd& X, const std::vector<int>& y, const SvmParams& params,
                           unsigned seed, int* iteration_cap_warnings) {
  const int n = static_cast<int>(X.rows()), d = static_cast<int>(X.cols());
  if (n != static_cast<int>(y.size()) || n < 2 || d < 1)
    throw InvalidInputError("training_data", "SVM training needs at least 2 samples with features and one label each");
  const int k = *std::max_element(y.begin(), y.end()) + 1;
  std::vector<int> count(k, 0);
  for (int label : y) {
    if (label < 0) throw InvalidInputError("training_data", "negative class label");
    ++count[label];
  }
  if (k < 2 || std::any_of(count.begin(), count.end(), [](int c) { return c == 0; }))
    throw InvalidInputError("training_data", "SVM training needs at least 2 classes, each with a sample");
  if (!X.allFinite()) throw InvalidInputError("training_data", "training features contain NaN or infinity");

  // Stable sort by label: libsvm orders classes by first appearance; this makes that order 0..k-1.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return y[a] < y[b]; });
  std::vector<svm_node> nodes;
  nodes.reserve(static_cast<std::size_t>(n) * (d + 1));
  std::vector<double> targets(n);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = X;
  for (int i = 0; i < n; ++i) {
    append_dense(nodes, rows.row(order[i]).data(), d);
    targets[i] = y[order[i]];
  }
  std::vector<svm_node*> xs(n);
  for (int i = 0; i < n; ++i) xs[i] = nodes.data() + static_cast<std::size_t>(i) * (d + 1);
  svm_problem problem{n, targets.data(), xs.data()};

  svm_parameter param{};
  param.svm_type = C_SVC;
  param.kernel_type = RBF;
  param.gamma = params.gamma;
  param.C = params.C;
  param.cache_size = params.cache_mb;
  param.eps = params.tolerance;
  param.shrinking = params.shrinking ? 1 : 0;
  param.probability = params.probability ? 1 : 0;
  if (const char* error = svm_check_parameter(&problem, &param))
    throw InvalidInputError("training_parameters", std::string("libsvm refused the parameters: ") + error);

  svm_model* model = nullptr;
  {
    IterationCapCounter cap;
    if (params.probability) {
      std::lock_guard lock(rand_mutex());
      std::srand(seed);
      model = svm_train(&problem, &param);
    } else {
      model = svm_train(&problem, &param);  // no rand() without probability estimates
    }
    if (iteration_cap_warnings) *iteration_cap_warnings = cap.warnings();
  }

  // Copy out while the training nodes are still alive, then free libsvm's struct (free_sv == 0: it does not
  // free the nodes, which we own).
  SvmModelData data;
  data.C = params.C;
  data.gamma = params.gamma;
  data.n_features = d;
  data.n_classes = model->nr_class;
  data.labels.assign(model->label, model->label + model->nr_class);
  data.n_sv.assign(model->nSV, model->nSV + model->nr_class);
  const int l = model->l;
  data.support_vectors.setZero(l, d);
  for (int i = 0; i < l; ++i)
    for (const svm_node* p = model->SV[i]; p->index != -1; ++p) data.support_vectors(i, p->index - 1) = p->value;
  data.sv_coef.resize(model->nr_class - 1, l);
  for (int r = 0; r < model->nr_class - 1; ++r)
    for (int i = 0; i < l; ++i) data.sv_coef(r, i) = model->sv_coef[r][i];
  const int pairs = model->nr_class * (model->nr_class - 1) / 2;
  data.rho.assign(model->rho, model->rho + pairs);
  if (model->probA && model->probB) {
    data.prob_a.assign(model->probA, model->probA + pairs);
    data.prob_b.assign(model->probB, model->probB + pairs);
  }
  svm_free_and_destroy_model(&model);
  return SvmEngine(std::move(data));
}

namespace {

// libsvm's input for one feature vector, after checking its length against the model.
std::vector<svm_node> feature_nodes(const SvmModelData& d, const Eigen::Ref<const Eigen::VectorXd>& x) {
  if (x.size() != d.n_features)
    throw InvalidInputError("feature_mismatch", "the SVM expects " + std::to_string(d.n_features) +
                                                    " features, got " + std::to_string(x.size()));
  const Eigen::VectorXd copy = x;
  std::vector<svm_node> nodes;
  nodes.reserve(d.n_features + 1);
  append_dense(nodes, copy.data(), d.n_features);
  return nodes;
}

}  // namespace

SvmOutput SvmEngine::predict(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  const auto& d = impl_->data;
  const std::vector<svm_node> nodes = feature_nodes(d, x);
  const int k = d.n_classes;
  std::vector<double> dec(static_cast<std::size_t>(k) * (k - 1) / 2);
  SvmOutput out;
  out.label = static_cast<int>(svm_predict_values(&impl_->view, nodes.data(), dec.data()));
  // Re-index everything by label (internal class order is labels[], a permutation).
  out.votes.assign(k, 0.0);
  out.decision.assign(dec.size(), 0.0);
  auto pair_index = [k](int i, int j) { return i * k - i * (i + 1) / 2 + (j - i - 1); };  // i < j
  int p = 0;
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j, ++p) {
      const int li = d.labels[i], lj = d.labels[j];
      out.votes[dec[p] > 0 ? li : lj] += 1;
      if (li < lj) out.decision[pair_index(li, lj)] = dec[p];
      else out.decision[pair_index(lj, li)] = -dec[p];
    }
  if (has_probability()) {
    std::vector<double> prob(k);
    svm_predict_probability(&impl_->view, nodes.data(), prob.data());
    out.probability.assign(k, 0.0);
    for (int i = 0; i < k; ++i) out.probability[d.labels[i]] = prob[i];
  }
  return out;
}

int SvmEngine::predict_label(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  const std::vector<svm_node> nodes = feature_nodes(impl_->data, x);
  return static_cast<int>(svm_predict(&impl_->view, nodes.data()));  // votes only, no probabilities
}

}  // namespace wish
