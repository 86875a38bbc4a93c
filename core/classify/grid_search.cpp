#include "core/classify/grid_search.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>

#include "core/classify/svm_engine.hpp"

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

namespace {

Eigen::MatrixXd rows_of(const Eigen::MatrixXd& X, const std::vector<int>& idx) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(idx.size()), X.cols());
  for (std::size_t i = 0; i < idx.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = X.row(idx[i]);
  return out;
}

}  // namespace

GridSearchResult grid_search(const Eigen::MatrixXd& X, const std::vector<int>& y, const std::vector<Split>& splits,
                             const GridSearchOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  GridSearchResult r;
  r.Cs = options.Cs;
  r.gammas = options.gammas;
  const int nc = static_cast<int>(r.Cs.size()), ng = static_cast<int>(r.gammas.size());
  r.mean_score.setZero(nc, ng);
  r.std_score.setZero(nc, ng);
  // Training sets per split once; each cell trains on every split.
  std::vector<Eigen::MatrixXd> train_x, test_x;
  std::vector<std::vector<int>> train_y, test_y;
  for (const Split& s : splits) {
    train_x.push_back(rows_of(X, s.train));
    test_x.push_back(rows_of(X, s.test));
    std::vector<int> a, b;
    for (int i : s.train) a.push_back(y[i]);
    for (int i : s.test) b.push_back(y[i]);
    train_y.push_back(std::move(a));
    test_y.push_back(std::move(b));
  }
  parallel_for(nc * ng, options.jobs, [&](int cell) {
    const int ci = cell / ng, gi = cell % ng;
    SvmParams params;
    params.C = r.Cs[ci];
    params.gamma = r.gammas[gi];
    params.probability = false;  // accuracy needs votes only; no rand(), so cells run concurrently
    std::vector<double> scores;
    for (std::size_t s = 0; s < splits.size(); ++s) {
      const SvmEngine svm = SvmEngine::train(train_x[s], train_y[s], params, 0);
      std::size_t correct = 0;
      for (Eigen::Index i = 0; i < test_x[s].rows(); ++i)
        correct += svm.predict_label(test_x[s].row(i).transpose()) == test_y[s][static_cast<std::size_t>(i)];
      scores.push_back(static_cast<double>(correct) / static_cast<double>(test_x[s].rows()));
    }
    double sum = 0;
    for (double v : scores) sum += v;  // sequential, as numpy for short arrays
    const double mean = sum / static_cast<double>(scores.size());
    double var = 0;
    for (double v : scores) var += (v - mean) * (v - mean);
    r.mean_score(ci, gi) = mean;
    r.std_score(ci, gi) = std::sqrt(var / static_cast<double>(scores.size()));
  });
  r.best_score = -1;
  for (int ci = 0; ci < nc; ++ci)
    for (int gi = 0; gi < ng; ++gi)
      if (r.mean_score(ci, gi) > r.best_score) {
        r.best_score = r.mean_score(ci, gi);
        r.best_c = ci;
        r.best_gamma = gi;
      }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace wish
