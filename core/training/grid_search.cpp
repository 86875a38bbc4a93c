#include "core/training/grid_search.hpp"

#include <algorithm>
#include <atomic>
#include <limits>
#include <numeric>
#include <optional>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>

#include "core/classify/svm_engine.hpp"
#include "core/common/cpu_budget.hpp"
#include "core/common/errors.hpp"
#include "core/training/decision_spread.hpp"
#include "core/training/precomputed_kernel.hpp"

namespace wish {

std::vector<double> decade_grid(int first_exponent, int last_exponent) {
  std::vector<double> v;
  for (int e = first_exponent; e <= last_exponent; ++e) v.push_back(std::pow(10.0, e));
  return v;
}

void parallel_for(int n, int jobs, const std::function<void(int)>& f) {
  if (jobs <= 0) jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  jobs = std::min(jobs, std::max(n, 1));
  std::atomic<int> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (int i; (i = next.fetch_add(1)) < n;) {
      try {
        f(i);
      } catch (...) {
        std::lock_guard lock(error_mutex);
        if (!error) error = std::current_exception();
        next = n;
      }
    }
  };
  if (jobs == 1) {
    worker();
  } else {
    std::vector<std::thread> threads;
    for (int t = 0; t < jobs; ++t) threads.emplace_back(worker);
    for (auto& t : threads) t.join();
  }
  if (error) std::rethrow_exception(error);
}

bool GridSearchResult::cell_offset_decided(int ci, int gi) const {
  return narrow_fits.size() && !std::isnan(mean_score(ci, gi)) && offset_decided(narrow_fits(ci, gi), splits_per_cell);
}

bool EarlyStopRow::stop_after(double mean, bool offset_decided) {
  if (first_ < 0) first_ = mean;
  if (offset_decided) return false;  // its score is the splits' class balance: neither a peak nor a fall
  // Only a row that has risen above its first cell can have passed its peak; a flat start (every sample in one
  // class's region, as at the tiny gammas) is not a plateau.
  const bool risen = best_ > first_;
  fallen_ = risen && mean <= best_ - drop_ ? fallen_ + 1 : 0;
  best_ = std::max(best_, mean);
  return fallen_ >= patience_;
}

namespace {

Eigen::MatrixXd rows_of(const Eigen::MatrixXd& X, const std::vector<int>& idx) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(idx.size()), X.cols());
  for (std::size_t i = 0; i < idx.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = X.row(idx[i]);
  return out;
}

}  // namespace

SplitMatrices::SplitMatrices(const Eigen::MatrixXd& X, const std::vector<int>& y, const std::vector<Split>& splits) {
  for (const Split& s : splits) {
    train_x.push_back(rows_of(X, s.train));
    test_x.push_back(rows_of(X, s.test));
    std::vector<int> a;
    for (int i : s.train) a.push_back(y[i]);
    train_y.push_back(std::move(a));
  }
}

PrecomputedKernel::FitScore fit_split(const PrecomputedKernel* kernel, const SplitMatrices& rows,
                                      const std::vector<Split>& splits, std::size_t s, const std::vector<int>& y,
                                      const SvmParams& params) {
  const Split& split = splits[s];
  if (kernel) return kernel->fit_and_score(split.train, split.test, y, params);
  PrecomputedKernel::FitScore score;
  const SvmEngine svm = SvmEngine::train(rows.train_x[s], rows.train_y[s], params, 0, &score.iteration_cap_warnings);
  for (std::size_t i = 0; i < split.test.size(); ++i)
    score.correct += svm.predict_label(rows.test_x[s].row(static_cast<Eigen::Index>(i)).transpose()) == y[split.test[i]];
  std::vector<int> positions(split.train.size());
  for (std::size_t i = 0; i < positions.size(); ++i) positions[i] = static_cast<int>(i);
  score.decision_spread = fit_decision_spread(svm.data().labels, positions, rows.train_y[s], [&](int i) {
    return svm.predict(rows.train_x[s].row(static_cast<Eigen::Index>(i)).transpose()).decision;
  });
  return score;
}

namespace {

struct CellStats {
  double mean = 0, std = 0;
};

CellStats stats_of(const std::vector<double>& scores) {
  double sum = 0;
  for (double v : scores) sum += v;  // sequential, as numpy for short arrays
  const double mean = sum / static_cast<double>(scores.size());
  double var = 0;
  for (double v : scores) var += (v - mean) * (v - mean);
  return {mean, std::sqrt(var / static_cast<double>(scores.size()))};
}

// Cell (ci, gi) fitted on every split: its mean and spread of validation accuracy, the fits that hit libsvm's
// iteration cap, the fits decided by the offset (decision_spread.hpp) and its CPU seconds, stored in r. With a kernel
// the fits use that precomputed matrix, else libsvm's own RBF on `rows`.
void score_cell(const PrecomputedKernel* kernel, const SplitMatrices& rows, const std::vector<Split>& splits,
                const std::vector<int>& y, int ci, int gi, GridSearchResult& r) {
  const double cell_start = CpuBudget::thread_cpu_seconds();
  SvmParams params;
  params.C = r.Cs[ci];
  params.gamma = r.gammas[gi];
  params.probability = false;  // accuracy needs votes only; no rand(), so cells run concurrently
  std::vector<double> scores;
  int capped = 0, narrow = 0;
  for (std::size_t s = 0; s < splits.size(); ++s) {
    const auto fit = fit_split(kernel, rows, splits, s, y, params);
    capped += fit.iteration_cap_warnings > 0;
    narrow += fit.decision_spread < kMarginSpread;
    scores.push_back(static_cast<double>(fit.correct) / static_cast<double>(splits[s].test.size()));
  }
  const CellStats st = stats_of(scores);
  r.mean_score(ci, gi) = st.mean;
  r.std_score(ci, gi) = st.std;
  r.capped_fits(ci, gi) = capped;
  r.narrow_fits(ci, gi) = narrow;
  r.cell_cpu_seconds(ci, gi) = CpuBudget::thread_cpu_seconds() - cell_start;
}

// The search before issue 25, kept as the exhaustive reference (precomputed_kernel and early_stop both off): every
// cell in parallel, each fit with libsvm's own RBF kernel.
void exhaustive_rbf_cells(const Eigen::MatrixXd& X, const std::vector<int>& y, const std::vector<Split>& splits,
                          const GridSearchOptions& options, GridSearchResult& r) {
  const int nc = static_cast<int>(r.Cs.size()), ng = static_cast<int>(r.gammas.size());
  const SplitMatrices rows(X, y, splits);
  parallel_for(nc * ng, options.jobs, [&](int cell) {
    score_cell(nullptr, rows, splits, y, cell / ng, cell % ng, r);
  });
}

// Gamma rows in parallel; in each row one kernel matrix (or libsvm's RBF per fit), C ascending, early stop.
void row_wise_cells(const Eigen::MatrixXd& X, const std::vector<int>& y, const std::vector<Split>& splits,
                    const GridSearchOptions& options, GridSearchResult& r) {
  const int nc = static_cast<int>(r.Cs.size()), ng = static_cast<int>(r.gammas.size());
  std::vector<int> c_order(nc);
  std::iota(c_order.begin(), c_order.end(), 0);
  std::stable_sort(c_order.begin(), c_order.end(), [&](int a, int b) { return r.Cs[a] < r.Cs[b]; });
  const Eigen::MatrixXd D = options.precomputed_kernel ? pairwise_squared_distances(X) : Eigen::MatrixXd();
  const SplitMatrices rows = options.precomputed_kernel ? SplitMatrices() : SplitMatrices(X, y, splits);
  parallel_for(ng, options.jobs, [&](int gi) {
    std::optional<PrecomputedKernel> kernel;
    if (options.precomputed_kernel) kernel.emplace(D, r.gammas[gi]);
    EarlyStopRow rule(options.early_stop_drop, options.early_stop_patience);
    bool stopped = false;
    for (int ci : c_order) {
      if (stopped) {
        r.mean_score(ci, gi) = r.std_score(ci, gi) = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      score_cell(kernel ? &*kernel : nullptr, rows, splits, y, ci, gi, r);
      if (!options.early_stop) continue;
      stopped = rule.stop_after(r.mean_score(ci, gi),
                                offset_decided(r.narrow_fits(ci, gi), static_cast<int>(splits.size())));
    }
  });
}

}  // namespace

GridSearchResult grid_search(const Eigen::MatrixXd& X, const std::vector<int>& y, const std::vector<Split>& splits,
                             const GridSearchOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  GridSearchResult r;
  r.Cs = options.Cs;
  r.gammas = options.gammas;
  r.early_stop = options.early_stop;
  r.early_stop_drop = options.early_stop ? options.early_stop_drop : 0;
  r.early_stop_patience = options.early_stop ? options.early_stop_patience : 0;
  r.precomputed_kernel = options.precomputed_kernel;
  const int nc = static_cast<int>(r.Cs.size()), ng = static_cast<int>(r.gammas.size());
  if (options.early_stop && (options.early_stop_patience < 1 || !(options.early_stop_drop >= 0)))
    throw InvalidInputError("training_parameters", "early stop needs a patience >= 1 and a drop >= 0");
  r.mean_score.setZero(nc, ng);
  r.std_score.setZero(nc, ng);
  r.capped_fits.setZero(nc, ng);
  r.narrow_fits.setZero(nc, ng);
  r.splits_per_cell = static_cast<int>(splits.size());
  r.cell_cpu_seconds.setZero(nc, ng);
  if (!options.precomputed_kernel && !options.early_stop) exhaustive_rbf_cells(X, y, splits, options, r);
  else row_wise_cells(X, y, splits, options, r);
  // The best cell: the highest mean among the cells not decided by the offset, ties to the first in C-major order;
  // only when every scored cell is offset-decided, the best of those.
  r.best_score = -1;
  double best_offset_score = -1;
  int best_offset_c = 0, best_offset_gamma = 0;
  for (int ci = 0; ci < nc; ++ci)
    for (int gi = 0; gi < ng; ++gi) {
      if (std::isnan(r.mean_score(ci, gi))) {
        ++r.cells_skipped;
        continue;
      }
      r.fits += static_cast<int>(splits.size());
      if (r.cell_offset_decided(ci, gi)) {
        ++r.cells_offset_decided;
        if (r.mean_score(ci, gi) > best_offset_score) {
          best_offset_score = r.mean_score(ci, gi);
          best_offset_c = ci;
          best_offset_gamma = gi;
        }
      } else if (r.mean_score(ci, gi) > r.best_score) {
        r.best_score = r.mean_score(ci, gi);
        r.best_c = ci;
        r.best_gamma = gi;
      }
    }
  if (r.best_score < 0) {
    r.best_offset_decided = true;
    r.best_score = best_offset_score;
    r.best_c = best_offset_c;
    r.best_gamma = best_offset_gamma;
  }
  r.search_rows = static_cast<int>(X.rows());
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace wish
