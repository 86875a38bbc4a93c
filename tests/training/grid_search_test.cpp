// The grid search at scale (issue 25): the precomputed kernel gives the cells libsvm's own RBF kernel gives; early
// stop only skips cells, never changes one, and skips exactly where its rule says; fits that stop at libsvm's
// iteration cap are counted (per cell, per thread) and never printed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <thread>

#include "core/classify/libsvm_messages.hpp"
#include "core/classify/splits.hpp"
#include "core/classify/standard_scaler.hpp"
#include "core/classify/svm_engine.hpp"
#include "core/training/grid_search.hpp"
#include "core/training/training.hpp"
#include "tests/classify/classify_test_data.hpp"

namespace wish {
namespace {

using Data = testing::StandardizedData;
using testing::standardized;

TEST(GridSearch, PrecomputedKernelGivesTheCellsOfLibsvmsRbfKernel) {
  const Data d = standardized(4, 16, 3);
  const auto splits = stratified_shuffle_split(d.y, 5, 0.2, 9);
  GridSearchOptions rbf;
  rbf.Cs = decade_grid(-2, 4);  // below the corner where fits run to the iteration cap
  rbf.gammas = decade_grid(-4, 2);
  rbf.jobs = 2;
  rbf.precomputed_kernel = false;
  rbf.early_stop = false;
  GridSearchOptions pre = rbf;
  pre.precomputed_kernel = true;
  const GridSearchResult a = grid_search(d.X, d.y, splits, rbf), b = grid_search(d.X, d.y, splits, pre);
  ASSERT_EQ(b.cells_skipped, 0);
  EXPECT_EQ(b.fits, static_cast<int>(rbf.Cs.size() * rbf.gammas.size() * splits.size()));
  // The kernel values agree to rounding (exp of the same squared distance), so every vote does.
  for (Eigen::Index i = 0; i < a.mean_score.rows(); ++i)
    for (Eigen::Index j = 0; j < a.mean_score.cols(); ++j)
      EXPECT_NEAR(a.mean_score(i, j), b.mean_score(i, j), 1e-12) << "C " << rbf.Cs[i] << " gamma " << rbf.gammas[j];
  EXPECT_EQ(a.best_c, b.best_c);
  EXPECT_EQ(a.best_gamma, b.best_gamma);
}

TEST(GridSearch, EarlyStopSkipsCellsExactlyWhereItsRuleSaysAndChangesNone) {
  const Data d = standardized(4, 20, 5, 0.6);  // overlapping classes: accuracy falls off at large C
  const auto splits = stratified_shuffle_split(d.y, 4, 0.25, 2);
  GridSearchOptions all;
  all.Cs = decade_grid(-2, 6);
  all.gammas = decade_grid(-3, 2);
  all.jobs = 2;
  all.early_stop = false;
  GridSearchOptions stop = all;
  stop.early_stop = true;
  const GridSearchResult full = grid_search(d.X, d.y, splits, all), early = grid_search(d.X, d.y, splits, stop);
  EXPECT_GT(early.cells_skipped, 0) << "the data should make some row fall off";
  int skipped = 0;
  for (Eigen::Index g = 0; g < full.mean_score.cols(); ++g) {
    // Replay the rule on the exhaustive row: once the row has risen above its first cell, after `patience`
    // consecutive C not better than the best so far by more than `-drop` (drop 0: no better), every larger C is
    // skipped. A cell decided by the SVM's offset (decision_spread.hpp) is at most the row's start.
    double best = -1, first = -1;
    int fallen = 0;
    bool stopped = false;
    for (Eigen::Index c = 0; c < full.mean_score.rows(); ++c) {
      if (stopped) {
        EXPECT_TRUE(std::isnan(early.mean_score(c, g))) << "C " << all.Cs[c] << " gamma " << all.gammas[g];
        ++skipped;
        continue;
      }
      EXPECT_EQ(early.mean_score(c, g), full.mean_score(c, g)) << "C " << all.Cs[c] << " gamma " << all.gammas[g];
      const double v = full.mean_score(c, g);
      if (first < 0) first = v;
      if (full.cell_offset_decided(static_cast<int>(c), static_cast<int>(g))) continue;  // only the row's start
      fallen = best > first && v <= best - stop.early_stop_drop ? fallen + 1 : 0;
      best = std::max(best, v);
      stopped = fallen >= stop.early_stop_patience;
    }
  }
  EXPECT_EQ(early.cells_skipped, skipped);
  EXPECT_EQ(early.fits + skipped * static_cast<int>(splits.size()), full.fits);
  EXPECT_EQ(early.best_score, full.best_score);  // here the best cell sits before any fall-off
}

// The default search (precomputed kernel, early stop) against the exhaustive one (libsvm's RBF per fit, every cell)
// on the paper's whole 13 x 13 grid, on separable classes and on overlapping ones: a cell with the exhaustive search's best
// validation accuracy (on overlapping classes, where ties are rare, the same cell).
void expect_same_choice(const Data& d, const char* what, bool same_cell) {
  const Split holdout = stratified_shuffle_split(d.y, 1, 0.2, 7).front();
  Eigen::MatrixXd Xa(static_cast<Eigen::Index>(holdout.train.size()), d.X.cols());
  std::vector<int> ya;
  for (std::size_t i = 0; i < holdout.train.size(); ++i) {
    Xa.row(static_cast<Eigen::Index>(i)) = d.X.row(holdout.train[i]);
    ya.push_back(d.y[static_cast<std::size_t>(holdout.train[i])]);
  }
  const auto splits = stratified_shuffle_split(ya, 5, 0.2, 8);
  GridSearchOptions exhaustive;
  exhaustive.jobs = 2;
  exhaustive.precomputed_kernel = false;
  exhaustive.early_stop = false;
  GridSearchOptions ours;  // the defaults
  ours.jobs = 2;
  const GridSearchResult e = grid_search(Xa, ya, splits, exhaustive), o = grid_search(Xa, ya, splits, ours);
  EXPECT_GT(o.cells_skipped, 0) << what << ": the default rule should skip cells here";
  EXPECT_NEAR(o.best_score, e.best_score, 1e-12) << what;
  // The cell it picks is one of the exhaustive search's best (its score there is the same best score).
  EXPECT_NEAR(e.mean_score(o.best_c, o.best_gamma), e.best_score, 1e-12) << what;
  if (same_cell) {
    EXPECT_EQ(o.C(), e.C()) << what;
    EXPECT_EQ(o.gamma(), e.gamma()) << what;
  }
}

TEST(GridSearch, DefaultSearchPicksTheExhaustiveSearchsCell) {
  // Separable: many cells reach accuracy 1; a row that dips and comes back may be stopped before the exhaustive
  // search's first tie (C-major order), so only the score is the same, not necessarily the cell.
  expect_same_choice(standardized(3, 25, 11, 0.15), "separable classes", false);
  expect_same_choice(standardized(4, 25, 12, 0.6), "overlapping classes", true);
}

TEST(NestedCrossValidation, ParallelOuterFoldsGiveTheSequentialResult) {
  const auto samples = testing::synthetic_samples(3, 14, 21, 8, 0.5);
  FeatureSpec spec;
  spec.l_max = 6;
  spec.log_transform = true;
  Eigen::MatrixXd X;
  std::vector<int> y;
  std::vector<std::string> names;
  build_feature_matrix(samples, spec, X, y, names);
  NestedCvOptions one;
  one.outer_folds = 3;
  one.repeats = 2;
  one.inner_splits = 3;
  one.grid.Cs = decade_grid(-1, 3);
  one.grid.gammas = decade_grid(-3, 1);
  one.grid.jobs = 1;
  NestedCvOptions two = one;
  two.grid.jobs = 2;
  const NestedCvResult a = nested_cross_validation(X, y, one), b = nested_cross_validation(X, y, two);
  ASSERT_EQ(a.scores.size(), 6u);
  EXPECT_EQ(a.scores, b.scores);
  EXPECT_EQ(a.chosen, b.chosen);
  EXPECT_EQ(a.fits, b.fits);
  EXPECT_EQ(a.cells_skipped, b.cells_skipped);
}

// Two classes drawn from one distribution: no boundary exists; at gamma 0.1, C = 1e10 libsvm's solver runs to its
// iteration cap (10^7 iterations, a few seconds) on these 40 points, found by trying; at C = 1 it converges.
void hopeless(Eigen::MatrixXd& X, std::vector<int>& y) {
  std::mt19937_64 rng(17);
  X.resize(40, 3);
  for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = static_cast<double>(rng() >> 11) * 0x1.0p-53 - 0.5;
  y.assign(40, 0);
  for (int i = 0; i < 40; ++i) y[static_cast<std::size_t>(i)] = i % 2;
}

TEST(LibsvmMessages, IterationCapWarningsAreCountedPerThreadNotPrinted) {
  Eigen::MatrixXd X;
  std::vector<int> y;
  hopeless(X, y);
  SvmParams capped;
  capped.C = 1e10;
  capped.gamma = 0.1;
  capped.probability = false;
  SvmParams easy = capped;
  easy.C = 1;
  int warnings_capped = -1, warnings_easy = -1;
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  // The converging fit runs on another thread while the capped one runs: its count must stay its own.
  std::thread a([&] { (void)SvmEngine::train(X, y, capped, 0, &warnings_capped); });
  std::thread b([&] {
    for (int i = 0; i < 20; ++i) {
      int w = -1;
      (void)SvmEngine::train(X, y, easy, 0, &w);
      warnings_easy = std::max(warnings_easy, w);
    }
  });
  a.join();
  b.join();
  std::fprintf(stderr, "other text still reaches stderr\n");
  const std::string out = ::testing::internal::GetCapturedStdout(), err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(warnings_capped, 1);  // one pair of classes, one solver, stopped at the cap
  EXPECT_EQ(warnings_easy, 0) << "a converging fit on another thread got the other thread's warnings";
  EXPECT_EQ(out.find("max number of iterations"), std::string::npos) << out;
  EXPECT_EQ(err.find("max number of iterations"), std::string::npos) << err;
  EXPECT_NE(err.find("other text still reaches stderr"), std::string::npos) << err;
}

TEST(GridSearch, CountsCappedFitsPerCell) {
  Eigen::MatrixXd X;
  std::vector<int> y;
  hopeless(X, y);
  Split all;
  for (int i = 0; i < 40; ++i) (i % 5 == 0 ? all.test : all.train).push_back(i);
  GridSearchOptions o;
  o.Cs = {1, 1e10};
  o.gammas = {0.1};
  o.jobs = 1;
  o.early_stop = false;
  const GridSearchResult r = grid_search(X, y, {all}, o);
  // The same fit outside the grid (libsvm's own RBF kernel) says whether it stops at the cap.
  Eigen::MatrixXd Xa(static_cast<Eigen::Index>(all.train.size()), 3);
  std::vector<int> ya;
  for (std::size_t i = 0; i < all.train.size(); ++i) {
    Xa.row(static_cast<Eigen::Index>(i)) = X.row(all.train[i]);
    ya.push_back(y[static_cast<std::size_t>(all.train[i])]);
  }
  SvmParams p;
  p.C = 1e10;
  p.gamma = 0.1;
  p.probability = false;
  int direct = -1;
  (void)SvmEngine::train(Xa, ya, p, 0, &direct);
  ASSERT_GE(direct, 1) << "the data should make this fit run to the cap";
  EXPECT_EQ(r.capped_fits(0, 0), 0);
  EXPECT_EQ(r.capped_fits(1, 0), 1);
  EXPECT_EQ(r.total_capped_fits(), 1);
}

}  // namespace
}  // namespace wish
