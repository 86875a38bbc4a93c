#pragma once
// Successive halving over the (C, gamma) grid (Jamieson & Talwalkar 2016, "Non-stochastic best arm identification
// and hyperparameter optimization"; scikit-learn's HalvingGridSearchCV with the number of samples as the resource),
// the search `wish train` runs on large training sets (issue 40; the size rule is in search_plan.hpp).
//
// Every cell of the grid is scored on a small stratified subsample of the training rows; the best 1/factor of the
// cells go on to a subsample `factor` times larger, and so on, until the last rung scores the few cells left on
// `max_rows` rows (or all rows). The best cell of the last rung is the search's answer; the model is then fitted on
// all training rows (training.cpp), so the search subsample caps the search's cost, not the data the model sees.
// Why it is safe enough: the ranking of an RBF grid's cells on a few hundred rows already separates the good region
// (a band of C x gamma) from the bad one, and the last rungs decide within that band on thousands of rows; measured
// against the full grid in docs/benchmarks.md "Training that scales".
//
// Rung r scores its cells by the mean accuracy over `splits` stratified shuffle splits (validation_fraction) of its
// subsample, as grid_search does on all rows, with grid_search's early-stop rule along C within each gamma row
// (GridSearchOptions::early_stop): a cell past its row's peak in a rung is skipped there and goes no further. Without
// it the rungs' large-C cells dominate the cost (measured: 57 cells on 800 rows took 78 s, the full grid with early
// stop on the same rows 8 s). Subsamples are nested (rung r's rows are the first rows of rung
// r + 1's) and stratified (every prefix holds each class in its share, within one sample). Ties: the first cell in
// C-major order, as grid_search. Everything is deterministic for a seed, whatever the number of threads.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/training/grid_search.hpp"

namespace wish {

struct HalvingOptions {
  int factor = 3;            // eta: 1/factor of the cells survive a rung, the next rung has factor x the rows
  int max_rows = 2000;       // the last rung's subsample (0: every training row)
  int min_rows = 0;          // the first rung's subsample; 0: 20 per class and at least 5 of the smallest class
  int splits = 10;           // stratified shuffle splits per rung
  double validation_fraction = 0.2;
  int max_precomputed_rows = 3000;  // above: libsvm's own RBF kernel per fit (a precomputed one takes 16 n^2 bytes)
};

// X: standardised features, one sample per row; y in 0..k-1, every class with >= 2 samples.
// The result's mean_score holds each cell's score at the last rung it reached (cell_rung), rungs[] the schedule.
GridSearchResult successive_halving(const Eigen::MatrixXd& X, const std::vector<int>& y, const GridSearchOptions& grid,
                                    const HalvingOptions& options, std::uint64_t seed);

// The rows of each rung's subsample: a stratified order of 0..n-1 whose every prefix holds each class in proportion
// (class c's i-th shuffled member sits at key (i + 0.5) / n_c; ties by class). Exposed for tests.
std::vector<int> stratified_nested_order(const std::vector<int>& y, std::uint64_t seed);

}  // namespace wish
