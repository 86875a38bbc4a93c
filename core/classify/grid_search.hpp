#pragma once
// Hyper-parameter search as in paper §6 / Table 1: RBF C-SVM over a logarithmic grid (one decade per step,
// C in 1e-2..1e10, gamma in 1e-9..1e3: 13 x 13), each cell scored by the mean validation accuracy over
// stratified shuffle splits with a fixed seed. Cells run in parallel (std::thread, `jobs` workers).
// Best cell: the highest mean score, ties to the first cell in C-major order (C outer, gamma inner) — the
// order of scikit-learn's ParameterGrid({"C", "gamma"}) whose first best GridSearchCV picks.

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "core/classify/splits.hpp"

namespace wish {

std::vector<double> decade_grid(int first_exponent, int last_exponent);  // 10^first ... 10^last

struct GridSearchOptions {
  std::vector<double> Cs = decade_grid(-2, 10);
  std::vector<double> gammas = decade_grid(-9, 3);
  int jobs = 0;  // 0: std::thread::hardware_concurrency()
};

struct GridSearchResult {
  std::vector<double> Cs, gammas;
  Eigen::MatrixXd mean_score, std_score;  // Cs.size() by gammas.size()
  int best_c = 0, best_gamma = 0;         // indices
  double best_score = 0;
  double seconds = 0;
  double C() const { return Cs[best_c]; }
  double gamma() const { return gammas[best_gamma]; }
};

// X: standardised features, one sample per row; y in 0..k-1; splits index rows of X.
GridSearchResult grid_search(const Eigen::MatrixXd& X, const std::vector<int>& y, const std::vector<Split>& splits,
                             const GridSearchOptions& options = {});

// Runs f(i) for i in [0, n) on `jobs` threads (0: hardware concurrency); rethrows the first exception.
void parallel_for(int n, int jobs, const std::function<void(int)>& f);

}  // namespace wish
