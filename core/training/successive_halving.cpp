#include "core/training/successive_halving.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>

#include "core/classify/splits.hpp"
#include "core/classify/svm_engine.hpp"
#include "core/common/cpu_budget.hpp"
#include "core/common/errors.hpp"
#include "core/training/decision_spread.hpp"
#include "core/training/precomputed_kernel.hpp"

namespace wish {
namespace {

// The first rung's rows: 20 per class, and at least 5 of the smallest class (its share of the prefix), so that every
// stratified split of the rung holds every class on both sides.
int default_min_rows(const std::vector<int>& y) {
  std::map<int, int> counts;
  for (int v : y) ++counts[v];
  int smallest = static_cast<int>(y.size());
  for (const auto& [label, n] : counts) smallest = std::min(smallest, n);
  const double per_smallest = std::ceil(5.0 * static_cast<double>(y.size()) / smallest);
  return std::max(20 * static_cast<int>(counts.size()), static_cast<int>(per_smallest));
}

// The rows of each rung: rows[r] for r = 0..R-1, rows[R-1] = max_rows; R is the smaller of the rungs the cells need
// (halving until at most `factor` cells are left) and the rungs the rows allow (rows[0] >= min_rows).
std::vector<int> rung_rows(int cells, int min_rows, int max_rows, int factor) {
  int needed = 1;
  for (int c = cells; c > factor; c = (c + factor - 1) / factor) ++needed;
  int possible = 1;
  for (long long b = min_rows; b * factor <= max_rows; b *= factor) ++possible;
  const int R = std::min(needed, possible);
  std::vector<int> rows(R);
  double b = max_rows;
  for (int r = R - 1; r >= 0; --r, b /= factor) rows[r] = static_cast<int>(std::lround(b));
  return rows;
}

struct CellScore {
  double mean = 0, std = 0, cpu = 0;
  int capped = 0;
  int narrow = 0;        // split fits decided by the offset (decision_spread.hpp)
  bool skipped = false;  // by the early-stop rule along its gamma row, in this rung
  bool offset = false;   // most of its split fits were
};

// Scores `cells` (indices ci * ng + gi) on the stratified shuffle splits of the rows `subset` of X: one precomputed
// kernel per gamma when the subset is small enough, libsvm's own RBF kernel per fit otherwise. Gamma rows one after
// the other, each in ascending C under grid_search's early-stop rule (grid.early_stop): the cells past a row's peak
// are skipped in this rung, as the full grid skips them. The split fits of a cell run in parallel, each into its own
// slot, so the scores do not depend on the schedule.
std::vector<CellScore> score_cells(const Eigen::MatrixXd& X, const std::vector<int>& y, const std::vector<int>& subset,
                                   const std::vector<int>& cells, const GridSearchResult& r, const std::vector<Split>& splits,
                                   const GridSearchOptions& grid, const HalvingOptions& options) {
  const int ng = static_cast<int>(r.gammas.size());
  const int m = static_cast<int>(subset.size()), ns = static_cast<int>(splits.size());
  Eigen::MatrixXd Xr(m, X.cols());
  std::vector<int> yr(m);
  for (int i = 0; i < m; ++i) {
    Xr.row(i) = X.row(subset[i]);
    yr[i] = y[subset[i]];
  }
  const bool precomputed = grid.precomputed_kernel && m <= options.max_precomputed_rows;
  const Eigen::MatrixXd D = precomputed ? pairwise_squared_distances(Xr) : Eigen::MatrixXd();
  const SplitMatrices rows = precomputed ? SplitMatrices() : SplitMatrices(Xr, yr, splits);
  std::map<int, std::vector<int>> by_gamma;  // gamma index -> positions in `cells`, C ascending
  for (std::size_t p = 0; p < cells.size(); ++p) by_gamma[cells[p] % ng].push_back(static_cast<int>(p));
  std::vector<CellScore> out(cells.size());
  std::vector<double> accuracy(ns), cpu(ns);
  std::vector<int> capped(ns), narrow(ns);
  for (auto& [gi, positions] : by_gamma) {
    std::stable_sort(positions.begin(), positions.end(),
                     [&](int a, int b) { return r.Cs[cells[a] / ng] < r.Cs[cells[b] / ng]; });
    // A copy for the fits' lambda: clang 14 (the sanitizer build) cannot capture a structured binding (C++20 P1091).
    const double gamma = r.gammas[gi];
    std::optional<PrecomputedKernel> kernel;
    if (precomputed) kernel.emplace(D, gamma);
    EarlyStopRow rule(grid.early_stop_drop, grid.early_stop_patience);
    bool stopped = false;
    for (int p : positions) {
      if (stopped) {
        out[p].skipped = true;
        continue;
      }
      parallel_for(ns, grid.jobs, [&](int s) {
        const double start = CpuBudget::thread_cpu_seconds();
        SvmParams params;
        params.C = r.Cs[cells[p] / ng];
        params.gamma = gamma;
        params.probability = false;  // accuracy needs votes only; no rand(), so fits run concurrently
        const auto fit = fit_split(kernel ? &*kernel : nullptr, rows, splits, static_cast<std::size_t>(s), yr, params);
        accuracy[s] = static_cast<double>(fit.correct) / static_cast<double>(splits[s].test.size());
        capped[s] = fit.iteration_cap_warnings > 0;
        narrow[s] = fit.decision_spread < kMarginSpread;
        cpu[s] = CpuBudget::thread_cpu_seconds() - start;
      });
      CellScore& c = out[p];
      double sum = 0;
      for (int s = 0; s < ns; ++s) sum += accuracy[s];  // sequential, as grid_search
      c.mean = sum / ns;
      double var = 0;
      for (int s = 0; s < ns; ++s) {
        var += (accuracy[s] - c.mean) * (accuracy[s] - c.mean);
        c.capped += capped[s];
        c.narrow += narrow[s];
        c.cpu += cpu[s];
      }
      c.std = std::sqrt(var / ns);
      c.offset = offset_decided(c.narrow, ns);
      if (grid.early_stop) stopped = rule.stop_after(c.mean, c.offset);
    }
  }
  return out;
}

}  // namespace

std::vector<int> stratified_nested_order(const std::vector<int>& y, std::uint64_t seed) {
  std::map<int, std::vector<int>> groups;
  for (int i = 0; i < static_cast<int>(y.size()); ++i) groups[y[i]].push_back(i);
  struct Keyed {
    double key;
    int label, row;
  };
  std::vector<Keyed> keyed;
  std::uint64_t state = seed;
  for (auto& [label, members] : groups) {
    shuffle_indices(members, state);
    const double n = static_cast<double>(members.size());
    for (std::size_t i = 0; i < members.size(); ++i) keyed.push_back({(static_cast<double>(i) + 0.5) / n, label, members[i]});
  }
  std::stable_sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
    return a.key != b.key ? a.key < b.key : a.label < b.label;
  });
  std::vector<int> order;
  order.reserve(keyed.size());
  for (const Keyed& k : keyed) order.push_back(k.row);
  return order;
}

GridSearchResult successive_halving(const Eigen::MatrixXd& X, const std::vector<int>& y, const GridSearchOptions& grid,
                                    const HalvingOptions& options, std::uint64_t seed) {
  const auto start = std::chrono::steady_clock::now();
  if (options.factor < 2 || options.splits < 1 || options.max_rows < 0 || options.min_rows < 0 ||
      !(options.validation_fraction > 0 && options.validation_fraction < 1))
    throw InvalidInputError("training_parameters", "successive halving needs a factor >= 2, >= 1 split, row counts >= 0 "
                                                   "and a validation fraction in (0, 1)");
  const int n = static_cast<int>(X.rows());
  GridSearchResult r;
  r.method = "halving";
  r.Cs = grid.Cs;
  r.gammas = grid.gammas;
  r.precomputed_kernel = grid.precomputed_kernel;
  r.early_stop = grid.early_stop;
  r.early_stop_drop = grid.early_stop ? grid.early_stop_drop : 0;
  r.early_stop_patience = grid.early_stop ? grid.early_stop_patience : 0;
  const int nc = static_cast<int>(r.Cs.size()), ng = static_cast<int>(r.gammas.size());
  r.mean_score.setConstant(nc, ng, std::numeric_limits<double>::quiet_NaN());
  r.std_score.setConstant(nc, ng, std::numeric_limits<double>::quiet_NaN());
  r.capped_fits.setZero(nc, ng);
  r.narrow_fits.setZero(nc, ng);
  r.splits_per_cell = options.splits;  // every rung's splits
  r.cell_cpu_seconds.setZero(nc, ng);
  r.cell_rung.setConstant(nc, ng, -1);

  const int max_rows = options.max_rows > 0 ? std::min(options.max_rows, n) : n;
  const int min_rows = std::min(options.min_rows > 0 ? options.min_rows : default_min_rows(y), max_rows);
  const std::vector<int> schedule = rung_rows(nc * ng, min_rows, max_rows, options.factor);
  const std::vector<int> order = stratified_nested_order(y, seed);

  std::vector<int> candidates(static_cast<std::size_t>(nc) * ng);
  std::iota(candidates.begin(), candidates.end(), 0);  // C-major: ci * ng + gi, the tie order
  for (std::size_t rung = 0; rung < schedule.size(); ++rung) {
    const auto rung_start = std::chrono::steady_clock::now();
    std::vector<int> subset(order.begin(), order.begin() + schedule[rung]);
    std::sort(subset.begin(), subset.end());
    std::vector<int> ys;
    for (int i : subset) ys.push_back(y[i]);
    const auto splits = stratified_shuffle_split(ys, options.splits, options.validation_fraction,
                                                 seed + 0x9e3779b97f4a7c15ull * (rung + 1));
    const std::vector<CellScore> scores = score_cells(X, y, subset, candidates, r, splits, grid, options);
    int evaluated = 0;
    for (std::size_t p = 0; p < candidates.size(); ++p) {
      const int ci = candidates[p] / ng, gi = candidates[p] % ng;
      if (scores[p].skipped) {
        ++r.cells_skipped;
        continue;
      }
      ++evaluated;
      r.mean_score(ci, gi) = scores[p].mean;
      r.std_score(ci, gi) = scores[p].std;
      r.capped_fits(ci, gi) += scores[p].capped;
      r.narrow_fits(ci, gi) = scores[p].narrow;  // of the rung its mean_score comes from
      r.cell_cpu_seconds(ci, gi) += scores[p].cpu;
      r.cell_rung(ci, gi) = static_cast<int>(rung);
    }
    const int fits = evaluated * static_cast<int>(splits.size());
    r.fits += fits;
    r.rungs.push_back({schedule[rung], static_cast<int>(candidates.size()), static_cast<int>(splits.size()), fits,
                       std::chrono::duration<double>(std::chrono::steady_clock::now() - rung_start).count()});
    // Rank by mean accuracy, ties to the first cell in C-major order, the cells decided by the offset after all
    // others (grid_search.hpp); keep the best 1/factor for the next rung.
    std::vector<int> rank(candidates.size());
    std::iota(rank.begin(), rank.end(), 0);
    std::stable_sort(rank.begin(), rank.end(), [&](int a, int b) {
      if (scores[a].skipped != scores[b].skipped) return scores[b].skipped;  // skipped cells rank last
      if (scores[a].offset != scores[b].offset) return scores[b].offset;
      return scores[a].mean != scores[b].mean ? scores[a].mean > scores[b].mean : candidates[a] < candidates[b];
    });
    const std::size_t keep = std::min<std::size_t>(
        rung + 1 < schedule.size() ? (candidates.size() + options.factor - 1) / options.factor : 1, evaluated);
    std::vector<int> next;
    for (std::size_t i = 0; i < keep; ++i) next.push_back(candidates[rank[i]]);
    if (rung + 1 == schedule.size()) {
      r.best_c = next.front() / ng;
      r.best_gamma = next.front() % ng;
      r.best_score = scores[rank.front()].mean;
      r.best_offset_decided = scores[rank.front()].offset;
    }
    std::sort(next.begin(), next.end());
    candidates = std::move(next);
  }
  for (int ci = 0; ci < nc; ++ci)
    for (int gi = 0; gi < ng; ++gi) r.cells_offset_decided += r.cell_offset_decided(ci, gi);
  r.search_rows = schedule.back();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace wish
