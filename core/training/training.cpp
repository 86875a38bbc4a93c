#include "core/training/training.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <map>
#include <set>

#include "core/classify/classifier_state.hpp"
#include "core/classify/feature_pipeline.hpp"
#include "core/classify/novelty.hpp"
#include "core/classify/sha256.hpp"
#include "core/classify/standard_scaler.hpp"
#include "core/classify/svm_engine.hpp"
#include "core/common/errors.hpp"
#include "core/training/class_spectra.hpp"
#include "core/training/successive_halving.hpp"

namespace wish {
namespace {

Eigen::MatrixXd rows_of(const Eigen::MatrixXd& X, const std::vector<int>& idx) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(idx.size()), X.cols());
  for (std::size_t i = 0; i < idx.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = X.row(idx[i]);
  return out;
}
std::vector<int> pick(const std::vector<int>& v, const std::vector<int>& idx) {
  std::vector<int> out;
  for (int i : idx) out.push_back(v[i]);
  return out;
}

std::string iso_now(const std::string& fixed) {
  if (!fixed.empty()) return fixed;
  std::time_t t = std::time(nullptr);
  if (const char* epoch = std::getenv("SOURCE_DATE_EPOCH")) t = static_cast<std::time_t>(std::strtoll(epoch, nullptr, 10));
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// The search on (X_train, y_train): the full grid on the paper's StratifiedShuffleSplit, or successive halving with
// as many splits per rung (search_plan.hpp says which).
GridSearchResult search(const Eigen::MatrixXd& Xs, const std::vector<int>& y, SearchMethod method, int n_splits,
                        double fraction, std::uint64_t seed, const GridSearchOptions& grid, const HalvingOptions& halving) {
  if (method == SearchMethod::Halving) {
    HalvingOptions h = halving;
    h.splits = n_splits;
    h.validation_fraction = fraction;
    return successive_halving(Xs, y, grid, h, seed);
  }
  const auto splits = stratified_shuffle_split(y, n_splits, fraction, seed);
  return grid_search(Xs, y, splits, grid);
}

}  // namespace

std::string dataset_sha256(const std::vector<TrainingSample>& samples) {
  Sha256 sha;
  char buf[40];
  for (const auto& s : samples) {
    sha.update(s.label);
    sha.update("|");
    for (Eigen::Index i = 0; i < s.features.invariants.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%.17g,", s.features.invariants(i));
      sha.update(buf);
    }
    sha.update("|");
    for (Eigen::Index i = 0; i < s.features.global.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%.17g,", s.features.global(i));
      sha.update(buf);
    }
    sha.update("\n");
  }
  static const char* digits = "0123456789abcdef";
  std::string hex;
  for (auto b : sha.finish()) {
    hex += digits[b >> 4];
    hex += digits[b & 15];
  }
  return hex;
}

void build_feature_matrix(const std::vector<TrainingSample>& samples, const FeatureSpec& spec, Eigen::MatrixXd& X,
                          std::vector<int>& y, std::vector<std::string>& classes) {
  std::set<std::string> names;
  for (const auto& s : samples) names.insert(s.label);
  classes.assign(names.begin(), names.end());
  const auto d = static_cast<Eigen::Index>(feature_names(spec).size());
  X.resize(static_cast<Eigen::Index>(samples.size()), d);
  y.clear();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    try {
      X.row(static_cast<Eigen::Index>(i)) = apply_feature_pipeline(samples[i].features, spec).transpose();
    } catch (const InvalidInputError& e) {
      throw InvalidInputError("training_data", "sample '" + samples[i].id + "': " + e.what());
    }
    y.push_back(static_cast<int>(std::lower_bound(classes.begin(), classes.end(), samples[i].label) - classes.begin()));
  }
}

NestedCvResult nested_cross_validation(const Eigen::MatrixXd& X, const std::vector<int>& y,
                                       const NestedCvOptions& options) {
  NestedCvResult out;
  if (y.empty() || options.repeats <= 0) return out;
  std::map<int, int> counts;
  for (int v : y) ++counts[v];
  int min_class = static_cast<int>(y.size());
  for (const auto& [label, n] : counts) min_class = std::min(min_class, n);
  const int outer = std::min(options.outer_folds, min_class);
  if (outer < 2) return out;
  out.repeats = options.repeats;
  out.outer_folds = outer;
  // The outer folds are independent: they run in parallel on the grid's workers, each with a one-thread inner search
  // (finer-grained than the gamma rows of one inner grid, so the two cores stay busy), and are gathered in fold order
  // so the result does not depend on scheduling.
  struct Task {
    std::uint64_t seed_r = 0;
    std::size_t f = 0;
    Split fold;
  };
  std::vector<Task> tasks;
  for (int r = 0; r < options.repeats; ++r) {
    const std::uint64_t seed_r = options.seed + 1000 * static_cast<std::uint64_t>(r);
    const auto folds = stratified_k_fold(y, outer, seed_r);
    for (std::size_t f = 0; f < folds.size(); ++f) tasks.push_back({seed_r, f, folds[f]});
  }
  struct FoldResult {
    bool done = false;
    double score = 0;
    GridSearchResult inner;
  };
  std::vector<FoldResult> results(tasks.size());
  GridSearchOptions inner_grid = options.grid;
  inner_grid.jobs = 1;
  parallel_for(static_cast<int>(tasks.size()), options.grid.jobs, [&](int t) {
    const Task& task = tasks[static_cast<std::size_t>(t)];
    const Eigen::MatrixXd Xa = rows_of(X, task.fold.train), Xb = rows_of(X, task.fold.test);
    const std::vector<int> ya = pick(y, task.fold.train), yb = pick(y, task.fold.test);
    const StandardScaler sc = StandardScaler::fit(Xa);
    const Eigen::MatrixXd Xas = sc.transform(Xa), Xbs = sc.transform(Xb);
    FoldResult& res = results[static_cast<std::size_t>(t)];
    try {
      res.inner = search(Xas, ya, options.search, options.inner_splits, options.validation_fraction, task.seed_r + task.f + 1,
                         inner_grid, options.halving);
    } catch (const InvalidInputError&) {
      return;  // an outer fold too small for the inner split; reported through the fold count
    }
    SvmParams p;
    p.C = res.inner.C();
    p.gamma = res.inner.gamma();
    p.probability = false;
    const SvmEngine m = SvmEngine::train(Xas, ya, p, 0);
    std::vector<int> pb;
    for (Eigen::Index i = 0; i < Xbs.rows(); ++i) pb.push_back(m.predict_label(Xbs.row(i).transpose()));
    res.score = accuracy(yb, pb);
    res.done = true;
  });
  for (const FoldResult& res : results) {
    if (!res.done) continue;
    out.scores.push_back(res.score);
    out.fits += res.inner.fits;
    out.capped_fits += res.inner.total_capped_fits();
    out.cells_skipped += res.inner.cells_skipped;
    out.chosen.emplace_back(res.inner.C(), res.inner.gamma());
    out.inner_scores.push_back(res.inner.best_score);
  }
  if (!out.scores.empty()) {
    double sum = 0;
    for (double s : out.scores) sum += s;
    out.mean = sum / static_cast<double>(out.scores.size());
    double var = 0;
    for (double s : out.scores) var += (s - out.mean) * (s - out.mean);
    out.std = std::sqrt(var / static_cast<double>(out.scores.size()));
    out.interval95 = cv_interval(out.scores, 1.0 / (outer - 1));
  }
  return out;
}

TrainingResult train_classifier(const std::vector<TrainingSample>& samples, const TrainOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  auto say = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  const FeatureSpec& spec = options.recipe.features;
  validate_feature_spec(spec);
  validate_recipe(options.recipe, "training_data");
  TrainingReport rep;
  {
    std::vector<std::string> kept, flagged;
    for (const auto& smp : samples) {
      kept.push_back(smp.label);
      if (smp.off_recipe) flagged.push_back(smp.label);
    }
    rep.losses = summarize_losses(kept, options.losses, flagged);
    enforce_loss_policy(rep.losses, options.loss_policy);
  }
  rep.spec = spec;
  rep.seed = options.seed;
  rep.samples = static_cast<std::int64_t>(samples.size());
  rep.feature_names = feature_names(spec);
  rep.dataset_sha256 = dataset_sha256(samples);
  Eigen::MatrixXd X;
  std::vector<int> y;
  build_feature_matrix(samples, spec, X, y, rep.classes);
  const int k = static_cast<int>(rep.classes.size());
  rep.class_counts.assign(k, 0);
  for (int v : y) ++rep.class_counts[v];
  if (k < 2) throw InvalidInputError("training_data", "training needs at least 2 classes, got " + std::to_string(k));
  for (int c = 0; c < k; ++c)
    if (rep.class_counts[c] < 2)
      throw InvalidInputError("training_data", "class '" + rep.classes[c] + "' has " +
                                                   std::to_string(rep.class_counts[c]) + " sample(s); at least 2 are needed");

  // Seeds of the stages derived from the one seed, so changing one stage does not shift the others.
  const std::uint64_t seed_test = options.seed, seed_grid = options.seed + 1, seed_svm = options.seed + 2,
                      seed_nested = options.seed + 3;
  const Split holdout = stratified_shuffle_split(y, 1, options.test_fraction, seed_test).front();
  rep.train_indices = holdout.train;
  rep.test_indices = holdout.test;
  const Eigen::MatrixXd X_train = rows_of(X, holdout.train), X_test = rows_of(X, holdout.test);
  const std::vector<int> y_train = pick(y, holdout.train), y_test = pick(y, holdout.test);
  const StandardScaler scaler = StandardScaler::fit(X_train);
  const Eigen::MatrixXd Xs_train = scaler.transform(X_train), Xs_test = scaler.transform(X_test);

  const SearchPlan plan = plan_search(static_cast<int>(y_train.size()), options.scale);
  rep.search_reason = plan.reason;
  say("search: " + plan.reason);
  say("grid search: " + std::to_string(options.grid.Cs.size()) + " x " + std::to_string(options.grid.gammas.size()) +
      " cells x " + std::to_string(options.grid_splits) + " splits on " + std::to_string(y_train.size()) + " samples");
  rep.grid = search(Xs_train, y_train, plan.search, options.grid_splits, options.grid_validation_fraction, seed_grid,
                    options.grid, options.scale.halving);
  say("grid search: best C = " + std::to_string(rep.grid.C()) + ", gamma = " + std::to_string(rep.grid.gamma()) +
      ", validation accuracy " + std::to_string(rep.grid.best_score) + " on " + std::to_string(rep.grid.search_rows) +
      " rows (" + std::to_string(rep.grid.seconds) + " s; " + std::to_string(rep.grid.fits) + " fits, " +
      std::to_string(rep.grid.total_capped_fits()) + " stopped at libsvm's iteration cap, " +
      std::to_string(rep.grid.cells_skipped) + " cells skipped by early stop, " +
      std::to_string(rep.grid.cells_offset_decided) + " decided by the offset" +
      (rep.grid.best_offset_decided ? ", the chosen one too: every scored cell was" : "") + ")");

  SvmParams params;
  params.C = rep.grid.C();
  params.gamma = rep.grid.gamma();
  params.probability = options.probability;
  SvmEngine svm = SvmEngine::train(Xs_train, y_train, params, static_cast<unsigned>(seed_svm), &rep.final_fit_cap_warnings);
  std::vector<int> pred_train, pred_test;
  for (Eigen::Index i = 0; i < Xs_train.rows(); ++i) pred_train.push_back(svm.predict_label(Xs_train.row(i).transpose()));
  for (Eigen::Index i = 0; i < Xs_test.rows(); ++i) pred_test.push_back(svm.predict_label(Xs_test.row(i).transpose()));
  rep.train_accuracy = accuracy(y_train, pred_train);
  {
    std::vector<bool> predicted(rep.classes.size(), false);
    for (int p : pred_train) predicted[static_cast<std::size_t>(p)] = true;
    for (std::size_t c = 0; c < rep.classes.size(); ++c)
      if (!predicted[c]) rep.train_classes_never_predicted.push_back(rep.classes[c]);
    if (!rep.train_classes_never_predicted.empty())
      say("WARNING: the model predicts none of its training samples as " +
          std::to_string(rep.train_classes_never_predicted.size()) + " of " + std::to_string(rep.classes.size()) +
          " classes (training accuracy " + std::to_string(rep.train_accuracy) + ")");
  }
  rep.test = evaluate_predictions(y_test, pred_test, rep.classes);
  for (std::size_t i = 0; i < holdout.test.size(); ++i) {
    rep.test_ids.push_back(samples[holdout.test[i]].id);
    rep.test_true.push_back(rep.classes[y_test[i]]);
    rep.test_predicted.push_back(rep.classes[pred_test[i]]);
  }
  say("test split: accuracy " + std::to_string(rep.test.accuracy) + " on " + std::to_string(y_test.size()) + " samples");

  // Nested, repeated stratified CV: the whole selection procedure (scaler + grid search) inside each outer fold.
  const auto nested_start = std::chrono::steady_clock::now();
  if (options.nested_repeats > 0) {
    NestedCvOptions nested;
    nested.outer_folds = options.nested_outer_folds;
    nested.repeats = options.nested_repeats;
    nested.search = plan.search;
    nested.halving = options.scale.halving;
    nested.inner_splits = options.nested_inner_splits;
    nested.validation_fraction = options.grid_validation_fraction;
    nested.grid = options.grid;
    nested.seed = seed_nested;
    rep.nested = nested_cross_validation(X, y, nested);
    say("nested CV: " + std::to_string(rep.nested.scores.size()) + " outer folds done");
  }
  rep.seconds_nested = std::chrono::duration<double>(std::chrono::steady_clock::now() - nested_start).count();

  StandardScaler final_scaler = scaler;
  if (options.refit_on_all) {
    final_scaler = StandardScaler::fit(X);
    svm = SvmEngine::train(final_scaler.transform(X), y, params, static_cast<unsigned>(seed_svm), &rep.final_fit_cap_warnings);
  }
  auto state = std::make_shared<ClassifierModel::State>(std::move(svm));
  if (options.novelty) {
    // On the samples the final SVM was fitted on, in its standardised space.
    state->novelty = options.refit_on_all
                         ? calibrate_novelty(final_scaler.transform(X), y, options.novelty_k, options.novelty_quantile,
                                             options.novelty_distance, options.novelty_folds, options.seed)
                         : calibrate_novelty(Xs_train, y_train, options.novelty_k, options.novelty_quantile,
                                             options.novelty_distance, options.novelty_folds, options.seed);
    state->novelty->rule = options.novelty_rule;
    for (int c = 0; c < k; ++c)
      rep.novelty_class_thresholds.push_back(novelty_threshold(*state->novelty, options.novelty_quantile, c));
    rep.novelty_threshold = *std::max_element(rep.novelty_class_thresholds.begin(), rep.novelty_class_thresholds.end());
    rep.novelty_quantile = options.novelty_quantile;
    rep.novelty_folds = state->novelty->calibration_folds;
    if (!options.refit_on_all)  // the test split is new to this model: how many of the known types it flags
      for (Eigen::Index i = 0; i < Xs_test.rows(); ++i) {
        const NoveltyAssessment a = assess_novelty(*state->novelty, Xs_test.row(i).transpose(), 0,
                                                   state->svm.predict(Xs_test.row(i).transpose()).label);
        rep.test_novelty.push_back(a.score);
        rep.test_novel.push_back(a.novel);
      }
  }
  state->name = options.name;
  state->version = options.version;
  state->classes = rep.classes;
  state->recipe = options.recipe;
  state->scaler = final_scaler;
  TrainingSummary& t = state->summary;
  t.dataset_sha256 = rep.dataset_sha256;
  t.trained_at = iso_now(options.trained_at);
  t.samples = rep.samples;
  t.best_c = rep.grid.C();
  t.best_gamma = rep.grid.gamma();
  t.grid_score = rep.grid.best_score;
  t.test_accuracy = rep.test.accuracy;
  t.nested_cv_mean = rep.nested.mean;
  t.nested_cv_std = rep.nested.std;
  t.notes = options.notes;
  if (!t.notes.empty()) t.notes += " ";
  t.notes += std::string("seed ") + std::to_string(options.seed) + (options.refit_on_all ? "; refit on all samples" : "; fit on the training split");
  t.class_spectra = class_spectra(samples, rep.classes);
  rep.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {ClassifierModel(finalize_state(std::move(state))), std::move(rep)};
}

}  // namespace wish
