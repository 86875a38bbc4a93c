#pragma once
// Hyper-parameter search as in paper §6 / Table 1: RBF C-SVM over a logarithmic grid (one decade per step,
// C in 1e-2..1e10, gamma in 1e-9..1e3: 13 x 13), each cell scored by the mean validation accuracy over
// stratified shuffle splits with a fixed seed. Cells run in parallel (std::thread, `jobs` workers).
// Best cell: the highest mean score, ties to the first cell in C-major order (C outer, gamma inner) — the
// order of scikit-learn's ParameterGrid({"C", "gamma"}) whose first best GridSearchCV picks.
//
// At scale (issue 25) the default search differs from the exhaustive one in two ways, both options:
//  * precomputed kernel: one RBF kernel matrix per gamma over all samples serves every C and every split of that
//    gamma's row (precomputed_kernel.hpp); the gamma rows run in parallel, each row's cells in ascending C.
//  * early stop (the rule): within a gamma row, C runs from small to large; let b be the row's best mean
//    validation accuracy so far and f its first cell's. Once the row has risen (b > f), a C whose mean accuracy is
//    not above b - early_stop_drop (default drop 0: no better than the row's best) counts as fallen; the row stops
//    after `early_stop_patience` consecutive fallen C (default 1: the first C past the row's peak). The row's larger
//    C values are skipped: not evaluated, NaN in mean_score (null in the report, grey on the heat map). A flat
//    start (every validation sample in one class's region, as at the tiny gammas) is not a peak, so such a row runs
//    on. Why this is safe enough: along C an RBF row rises to a peak and then over-fits (falls) or stays flat; the
//    costly fits (libsvm's solver running long or to its iteration cap on overlapping classes) sit at large C past
//    the peak. Measured (docs/benchmarks.md "Training at scale"): on the 1,000-descriptor sets it picks the
//    exhaustive search's cell for each feature family with 8-12x less CPU; a row that dips and rises again past
//    its dip is the case it can miss (patience > 1 tolerates such dips, at a cost).
// Every fit that stops at libsvm's iteration cap (not converged) is counted per cell.
//
// Cells decided by the offset (decision_spread.hpp): a cell most of whose split fits have a decision spread below
// the margin width is never the best cell while any other cell was scored (if every cell is, the best of them is
// chosen and best_offset_decided says so), and for the early-stop rule it is at most the row's start, never its best
// or a fall (its score comes from the validation splits' class balance, not from the kernel: a high one must not stop
// the row before the kernel's cells). Why: such a cell can win on the balanced validation splits and then, refitted
// on all rows with their real imbalance, put every sample into the larger class (measured on demo48: validation
// 0.812, the final model's training accuracy 0.368).

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/classify/splits.hpp"
#include "core/training/precomputed_kernel.hpp"

namespace wish {

std::vector<double> decade_grid(int first_exponent, int last_exponent);  // 10^first ... 10^last

struct GridSearchOptions {
  std::vector<double> Cs = decade_grid(-2, 10);
  std::vector<double> gammas = decade_grid(-9, 3);
  int jobs = 0;  // 0: std::thread::hardware_concurrency()
  bool precomputed_kernel = true;  // false: libsvm's own RBF kernel per fit (the search before issue 25)
  bool early_stop = true;          // the rule above; false: every cell (exhaustive)
  double early_stop_drop = 0;
  int early_stop_patience = 1;
};

// One rung of a successive-halving search (successive_halving.hpp): its cells scored on `rows` training rows.
struct HalvingRung {
  int rows = 0, candidates = 0, splits = 0, fits = 0;
  double seconds = 0;
};

struct GridSearchResult {
  std::string method = "grid";            // "grid" (every cell on all rows, early stop) or "halving"
  std::vector<double> Cs, gammas;
  Eigen::MatrixXd mean_score, std_score;  // Cs.size() by gammas.size(); NaN where early stop skipped the cell
  Eigen::MatrixXi capped_fits;            // per cell: split fits with a solver stopped at libsvm's iteration cap
  Eigen::MatrixXi narrow_fits;            // per cell: split fits decided by the offset (decision_spread.hpp)
  Eigen::MatrixXd cell_cpu_seconds;       // per cell: CPU time of its split fits (thread CPU clock; bench/ profiles)
  int fits = 0;                           // split fits run (cells evaluated x splits)
  int cells_skipped = 0;                  // by early stop
  int splits_per_cell = 0;                // split fits behind each scored cell's score (and its narrow_fits)
  int cells_offset_decided = 0;           // scored cells most of whose fits were decided by the offset
  bool best_offset_decided = false;       // every scored cell was: the best of them was chosen anyway
  bool early_stop = false;                // the options the search ran with (for the report)
  double early_stop_drop = 0;
  int early_stop_patience = 0;
  bool precomputed_kernel = false;
  std::vector<HalvingRung> rungs;         // halving only: the schedule, first rung first
  Eigen::MatrixXi cell_rung;              // halving only: per cell the last rung that scored it (its mean_score's)
  int search_rows = 0;                    // training rows the best cell was scored on (all rows for "grid")
  int best_c = 0, best_gamma = 0;         // indices
  double best_score = 0;
  double seconds = 0;
  int total_capped_fits() const { return capped_fits.size() ? capped_fits.sum() : 0; }
  bool cell_offset_decided(int ci, int gi) const;
  double C() const { return Cs[best_c]; }
  double gamma() const { return gammas[best_gamma]; }
};

// The early-stop rule above for one gamma row, fed the row's mean validation accuracies in ascending C (grid_search
// and each rung of successive_halving.hpp).
class EarlyStopRow {
 public:
  EarlyStopRow(double drop, int patience) : drop_(drop), patience_(patience) {}
  // Records the next cell's mean accuracy; true when the row stops after it (its larger C are skipped). A cell decided
  // by the offset only sets the row's start (when it is the first); it is neither the row's best nor a fall.
  bool stop_after(double mean, bool offset_decided = false);

 private:
  double drop_;
  int patience_;
  double first_ = -1, best_ = -1;
  int fallen_ = 0;
};

// The rows of each split as matrices, for fits with libsvm's own RBF kernel.
struct SplitMatrices {
  std::vector<Eigen::MatrixXd> train_x, test_x;
  std::vector<std::vector<int>> train_y;
  SplitMatrices() = default;
  SplitMatrices(const Eigen::MatrixXd& X, const std::vector<int>& y, const std::vector<Split>& splits);
};

// One fit of a cell (params, no probabilities) on splits[s], scored by votes on its test rows: on the precomputed
// `kernel` (over the rows y indexes) when there is one, else with libsvm's RBF kernel on `rows`.
PrecomputedKernel::FitScore fit_split(const PrecomputedKernel* kernel, const SplitMatrices& rows,
                                      const std::vector<Split>& splits, std::size_t s, const std::vector<int>& y,
                                      const SvmParams& params);

// X: standardised features, one sample per row; y in 0..k-1; splits index rows of X.
GridSearchResult grid_search(const Eigen::MatrixXd& X, const std::vector<int>& y, const std::vector<Split>& splits,
                             const GridSearchOptions& options = {});

// Runs f(i) for i in [0, n) on `jobs` threads (0: hardware concurrency); rethrows the first exception.
void parallel_for(int n, int jobs, const std::function<void(int)>& f);

}  // namespace wish
