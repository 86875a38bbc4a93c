// Training that scales (issue 40): successive halving scores cells exactly as the grid search does on the same rows
// and splits, promotes exactly the best 1/factor of a rung, keeps every subsample stratified and nested, and gives the
// same answer on any number of threads; the size rule picks the path it says; the nested CV's 95 % interval uses the
// right Student t quantiles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

#include "core/classify/splits.hpp"
#include "core/classify/standard_scaler.hpp"
#include "core/training/cv_interval.hpp"
#include "core/training/grid_search.hpp"
#include "core/training/search_plan.hpp"
#include "core/training/successive_halving.hpp"
#include "core/training/training.hpp"
#include "core/training/training_report.hpp"
#include "tests/classify/classify_test_data.hpp"

namespace wish {
namespace {

using Data = testing::StandardizedData;
using testing::standardized;

GridSearchOptions small_grid(int jobs) {
  GridSearchOptions g;
  g.Cs = decade_grid(-1, 4);
  g.gammas = decade_grid(-3, 1);
  g.jobs = jobs;
  return g;
}

TEST(SuccessiveHalving, EveryPrefixOfTheOrderIsStratified) {
  std::vector<int> y;
  for (int i = 0; i < 300; ++i) y.push_back(i % 7 == 0 ? 0 : (i % 3 == 0 ? 1 : 2));  // unequal classes
  std::map<int, int> total;
  for (int v : y) ++total[v];
  const std::vector<int> order = stratified_nested_order(y, 5);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> all(y.size());
  std::iota(all.begin(), all.end(), 0);
  ASSERT_EQ(sorted, all) << "not a permutation of the rows";
  std::map<int, int> seen;
  for (std::size_t b = 1; b <= order.size(); ++b) {
    ++seen[y[order[b - 1]]];
    for (const auto& [label, n] : total)
      EXPECT_LE(std::abs(seen[label] - static_cast<double>(b) * n / static_cast<double>(y.size())), 1.0)
          << "prefix " << b << ", class " << label;
  }
  EXPECT_EQ(stratified_nested_order(y, 5), order);
  EXPECT_NE(stratified_nested_order(y, 6), order);
}

TEST(SuccessiveHalving, OneRungIsTheFullGridOnTheSameSplits) {
  const Data d = standardized(3, 30, 31, 0.5);
  HalvingOptions h;
  h.splits = 4;
  h.min_rows = h.max_rows = static_cast<int>(d.y.size());  // one rung: every cell on every row
  const std::uint64_t seed = 77;
  const GridSearchResult halving = successive_halving(d.X, d.y, small_grid(2), h, seed);
  ASSERT_EQ(halving.rungs.size(), 1u);
  // The rung's splits: the rows in ascending order (the whole order), split with the first rung's seed.
  const auto splits = stratified_shuffle_split(d.y, h.splits, h.validation_fraction, seed + 0x9e3779b97f4a7c15ull);
  // The grid search with the same early-stop rule (the default) on the same splits: the same cells scored, the same
  // cells skipped.
  const GridSearchResult grid = grid_search(d.X, d.y, splits, small_grid(2));
  ASSERT_GT(grid.cells_skipped, 0) << "the data should make early stop skip some cells";
  for (Eigen::Index i = 0; i < grid.mean_score.rows(); ++i)
    for (Eigen::Index j = 0; j < grid.mean_score.cols(); ++j) {
      const bool skipped = std::isnan(grid.mean_score(i, j));
      EXPECT_EQ(std::isnan(halving.mean_score(i, j)), skipped) << i << ", " << j;
      if (!skipped) {
        EXPECT_NEAR(halving.mean_score(i, j), grid.mean_score(i, j), 1e-12) << i << ", " << j;
      }
      EXPECT_EQ(halving.cell_rung(i, j), skipped ? -1 : 0);
    }
  EXPECT_EQ(halving.best_c, grid.best_c);
  EXPECT_EQ(halving.best_gamma, grid.best_gamma);
  EXPECT_EQ(halving.fits, grid.fits);
  EXPECT_EQ(halving.cells_skipped, grid.cells_skipped);
  EXPECT_EQ(halving.method, "halving");
}

TEST(SuccessiveHalving, PromotesExactlyTheBestThirdOfEachRung) {
  const Data d = standardized(3, 60, 32, 0.5);  // 180 rows
  HalvingOptions h;
  h.splits = 3;
  h.min_rows = 20;
  h.max_rows = 180;
  GridSearchOptions every = small_grid(2);
  every.early_stop = false;  // every candidate scored: the counts below are exact
  const GridSearchResult r = successive_halving(d.X, d.y, every, h, 9);
  // 30 cells: 30 -> 10 -> 4 -> 2 needs 4 rungs, the rows allow 20 * 3^2 = 180: three rungs of 20, 60, 180 rows.
  ASSERT_EQ(r.rungs.size(), 3u);
  EXPECT_EQ(r.rungs[0].rows, 20);
  EXPECT_EQ(r.rungs[1].rows, 60);
  EXPECT_EQ(r.rungs[2].rows, 180);
  EXPECT_EQ(r.rungs[0].candidates, 30);
  EXPECT_EQ(r.rungs[1].candidates, 10);
  EXPECT_EQ(r.rungs[2].candidates, 4);
  EXPECT_EQ(r.fits, (30 + 10 + 4) * 3);
  EXPECT_EQ(r.search_rows, 180);
  // Rung 0 alone (one rung on the same 20 rows with the same seed) ranks the cells the way the full run promoted them.
  HalvingOptions first = h;
  first.max_rows = first.min_rows = 20;
  const GridSearchResult r0 = successive_halving(d.X, d.y, every, first, 9);
  const int ng = static_cast<int>(r.gammas.size());
  std::vector<int> cells(r.mean_score.size());
  std::iota(cells.begin(), cells.end(), 0);
  std::stable_sort(cells.begin(), cells.end(), [&](int a, int b) {  // cells decided by the offset rank last
    const bool oa = r0.cell_offset_decided(a / ng, a % ng), ob = r0.cell_offset_decided(b / ng, b % ng);
    if (oa != ob) return ob;
    return r0.mean_score(a / ng, a % ng) > r0.mean_score(b / ng, b % ng);
  });
  std::set<int> promoted(cells.begin(), cells.begin() + 10), reached;
  for (int c : cells)
    if (r.cell_rung(c / ng, c % ng) >= 1) reached.insert(c);
  EXPECT_EQ(reached, promoted);
  // The answer is the best of the last rung.
  EXPECT_EQ(r.cell_rung(r.best_c, r.best_gamma), 2);
  for (Eigen::Index i = 0; i < r.mean_score.rows(); ++i)
    for (Eigen::Index j = 0; j < r.mean_score.cols(); ++j)
      if (r.cell_rung(i, j) == 2 && !r.cell_offset_decided(static_cast<int>(i), static_cast<int>(j))) {
        EXPECT_LE(r.mean_score(i, j), r.best_score);
      }
}

TEST(SuccessiveHalving, SameAnswerOnAnyThreadCountAndKernel) {
  const Data d = standardized(4, 40, 33, 0.6);
  HalvingOptions h;
  h.splits = 3;
  h.min_rows = 40;
  const GridSearchResult one = successive_halving(d.X, d.y, small_grid(1), h, 3);
  const GridSearchResult two = successive_halving(d.X, d.y, small_grid(2), h, 3);
  HalvingOptions rbf = h;
  rbf.max_precomputed_rows = 0;  // libsvm's own RBF kernel per fit
  const GridSearchResult plain = successive_halving(d.X, d.y, small_grid(2), rbf, 3);
  for (const GridSearchResult* other : {&two, &plain}) {
    EXPECT_EQ(one.cell_rung, other->cell_rung);
    for (Eigen::Index i = 0; i < one.mean_score.size(); ++i) {
      const double a = one.mean_score.data()[i], b = other->mean_score.data()[i];
      EXPECT_TRUE(std::isnan(a) ? std::isnan(b) : std::abs(a - b) < 1e-12) << i << ": " << a << " " << b;
    }
    EXPECT_EQ(one.best_c, other->best_c);
    EXPECT_EQ(one.best_gamma, other->best_gamma);
  }
}

TEST(SearchPlan, PicksThePathItsThresholdSays) {
  ScalePolicy p;
  p.halving_above_rows = 1000;
  EXPECT_EQ(plan_search(1000, p).search, SearchMethod::Grid);
  EXPECT_EQ(plan_search(1001, p).search, SearchMethod::Halving);
  EXPECT_NE(plan_search(1001, p).reason.find("1001 training rows > 1000"), std::string::npos);
  p.search = SearchMethod::Grid;  // asked for: the paper's search at any size
  EXPECT_EQ(plan_search(40000, p).search, SearchMethod::Grid);
  p.search = SearchMethod::Halving;
  EXPECT_EQ(plan_search(80, p).search, SearchMethod::Halving);
  EXPECT_EQ(search_method_from_name("halving"), SearchMethod::Halving);
  EXPECT_THROW(search_method_from_name("random"), InvalidInputError);
}

TEST(CvInterval, StudentTQuantilesAreTheClosedForms) {
  const double pi = std::acos(-1.0);
  EXPECT_NEAR(student_t_quantile(0.975, 1), std::tan(pi * 0.475), 1e-8);        // Cauchy
  EXPECT_NEAR(student_t_quantile(0.975, 2), 0.95 / std::sqrt(2 * 0.975 * 0.025), 1e-9);  // (2p-1)/sqrt(2p(1-p))
  EXPECT_NEAR(student_t_quantile(0.025, 7), -student_t_quantile(0.975, 7), 1e-9);
  EXPECT_NEAR(student_t_quantile(0.5, 9), 0.0, 1e-9);
  // df -> infinity: the normal quantile, Phi^-1(0.975) = sqrt(2) erfinv(0.95); check Phi(q) instead.
  const double q = student_t_quantile(0.975, 1000000);
  EXPECT_NEAR(0.5 * std::erfc(-q / std::sqrt(2.0)), 0.975, 1e-6);
  EXPECT_THROW(student_t_quantile(1.0, 3), InvalidInputError);
}

TEST(CvInterval, CorrectedResampledT) {
  EXPECT_FALSE(cv_interval({0.9}, 0.25).has_value());
  const auto flat = cv_interval({0.8, 0.8, 0.8}, 0.25);
  ASSERT_TRUE(flat.has_value());
  EXPECT_NEAR(flat->low, 0.8, 1e-12);
  EXPECT_NEAR(flat->high, 0.8, 1e-12);
  const std::vector<double> s{0.80, 0.84, 0.82, 0.86, 0.78};
  const auto i = cv_interval(s, 0.25).value();
  const double mean = 0.82, var = (4e-4 + 4e-4 + 0 + 16e-4 + 16e-4) / 4;
  const double half = student_t_quantile(0.975, 4) * std::sqrt((0.2 + 0.25) * var);
  EXPECT_NEAR(i.low, mean - half, 1e-12);
  EXPECT_NEAR(i.high, mean + half, 1e-12);
  // Wider than the naive interval (the folds share training samples), clipped to [0, 1].
  EXPECT_GT(i.high - i.low, 2 * student_t_quantile(0.975, 4) * std::sqrt(var / 5));
  EXPECT_LE(cv_interval({0.99, 1.0, 0.97, 1.0}, 0.33)->high, 1.0);
}

TEST(Training, HalvingPathIsReportedAndReproducible) {
  const auto samples = testing::synthetic_samples(3, 40, 34);
  auto opts = testing::quick_train_options(11);
  opts.scale.search = SearchMethod::Auto;
  opts.scale.halving_above_rows = 50;  // 96 training rows: halving
  opts.scale.halving.max_rows = 60;
  opts.scale.halving.min_rows = 20;
  opts.nested_repeats = 2;
  const auto r = train_classifier(samples, opts);
  EXPECT_EQ(r.report.grid.method, "halving");
  EXPECT_NE(r.report.search_reason.find("successive halving"), std::string::npos) << r.report.search_reason;
  EXPECT_EQ(r.report.grid.search_rows, 60);
  EXPECT_EQ(r.report.nested.repeats, 2);
  EXPECT_EQ(r.report.nested.scores.size(), 6u);  // 2 repeats x 3 folds, each inner search halving on 80 rows
  EXPECT_TRUE(r.report.nested.interval95.has_value());
  EXPECT_EQ(r.model.training_summary().samples, 120);
  EXPECT_NE(training_report_table(r.report).find("halving rungs"), std::string::npos);
  const auto again = train_classifier(samples, opts);
  EXPECT_EQ(again.model.to_json_text(), r.model.to_json_text());
  EXPECT_EQ(again.report.nested.scores, r.report.nested.scores);
}

}  // namespace
}  // namespace wish
