#pragma once
// Training a ClassifierModel (paper §6; docs/design/classification.md): feature pipeline -> stratified 20 % test split ->
// z-score fitted on the training split -> grid search (StratifiedShuffleSplit, fixed seed) -> RBF C-SVM with
// Platt probabilities at the best (C, gamma) -> test accuracy, confusion matrix, per-class P/R/F1 -> nested,
// repeated stratified CV (outer k-fold repeated; inner grid search on each outer training fold, scaler refitted
// per fold) for an honest estimate. Everything is deterministic for a seed.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/classify/classifier_model.hpp"
#include "core/training/cv_interval.hpp"
#include "core/training/grid_search.hpp"
#include "core/training/metrics.hpp"
#include "core/training/search_plan.hpp"
#include "core/training/training_losses.hpp"

namespace wish {

struct TrainingSample {
  std::string id;     // file name or path (reports only)
  std::string label;  // class name
  ShapeFeatures features;
  bool off_recipe = false;  // its map came from another method than the recipe's (kept by accept_flagged)
  // A canonical recipe: the relaxation to the canonical map stopped at its budget or step cap (kept: the recipe's
  // descriptor; the path-dependence that remains, issue 37).
  bool canonical_unconverged = false;
};

struct TrainOptions {
  std::string name = "wish-svm";
  std::string version = "1";
  DescriptorRecipe recipe;         // recorded in the model: how the features were computed (recipe.features: the pipeline)
  GridSearchOptions grid;          // C, gamma grid and jobs
  ScalePolicy scale;               // which search at which size (search_plan.hpp)
  int grid_splits = 10;            // StratifiedShuffleSplit n_splits (scikit-learn's default)
  double grid_validation_fraction = 0.2;
  double test_fraction = 0.2;      // the paper's stratified hold-out
  int nested_outer_folds = 5;
  int nested_repeats = 2;          // 0: skip nested CV
  int nested_inner_splits = 5;
  bool refit_on_all = false;       // false: the shipped model is the one measured on the test split
  bool novelty = true;             // calibrate the novelty figure (novelty.hpp) on the final fit's samples
  bool probability = true;         // Platt probabilities on the final fit; off where the model is not kept (the
                                   // family comparison): the votes, so the test accuracy, are the same either way
  int novelty_k = 3;               // per class; 3 flagged more left-out members than 5 at the same false-flag rate (docs/benchmarks.md)
  double novelty_quantile = 0.99;  // the model's default threshold quantile
  NoveltyDistance novelty_distance = NoveltyDistance::Whitened;  // format 5; Euclidean: format 4's figure
  int novelty_folds = 0;           // 0: leave-one-out calibration scores (format 5); >= 2: cross-validated (format 6)
  NoveltyRule novelty_rule = NoveltyRule::NearestClass;  // PredictedClass: model format 7 (novelty.hpp)
  std::uint64_t seed = 42;
  // Meshes that did not become samples (refused, failed): counted per class in the report; training stops when a
  // class loses more than loss_policy.max_class_loss of its meshes (training_losses.hpp).
  std::vector<MeshLoss> losses;
  LossPolicy loss_policy;
  std::string trained_at;          // ISO 8601; empty: now, or SOURCE_DATE_EPOCH when set (reproducible files)
  std::string notes;
  std::function<void(const std::string&)> progress;  // optional, e.g. lines to stderr
};

struct NestedCvResult {
  int repeats = 0, outer_folds = 0;                 // as run (outer folds are capped at the smallest class)
  std::vector<double> scores;                       // one per outer fold and repeat
  std::vector<std::pair<double, double>> chosen;    // (C, gamma) picked by each inner search
  // Per outer fold, the inner search's best validation accuracy: computed on the fold's training rows only, so a
  // choice among feature families by it stays inside the fold (bench/family_selection.py).
  std::vector<double> inner_scores;
  double mean = 0, std = 0;
  std::optional<Interval> interval95;               // cv_interval.hpp; none for fewer than 2 scores
  // Over every inner grid search: split fits run, fits stopped at libsvm's iteration cap, cells skipped by early stop.
  int fits = 0, capped_fits = 0, cells_skipped = 0;
};

struct TrainingReport {
  std::vector<std::string> classes;
  std::vector<int> class_counts;
  std::vector<ClassLosses> losses;               // per class: meshes given, kept, lost by error code, flagged
  std::vector<std::string> feature_names;
  FeatureSpec spec;
  std::int64_t samples = 0;
  std::string dataset_sha256;
  std::uint64_t seed = 0;
  std::vector<int> train_indices, test_indices;  // into the samples given
  GridSearchResult grid;                         // grid.method: the search that ran ("grid" or "halving")
  std::string search_reason;                     // why that search (search_plan.hpp)
  double train_accuracy = 0;
  // Classes the shipped model predicts for none of its own training rows (a model that merged classes: the symptom
  // of a cell decided by the SVM's offset, decision_spread.hpp, or of classes it cannot tell apart); the report warns.
  std::vector<std::string> train_classes_never_predicted;
  int final_fit_cap_warnings = 0;                // the shipped model's fit: solvers stopped at libsvm's iteration cap
  ClassificationMetrics test;                    // on the hold-out split
  NestedCvResult nested;
  double seconds_total = 0, seconds_nested = 0;
  std::vector<std::string> test_ids;
  std::vector<std::string> test_true, test_predicted;
  std::vector<double> test_novelty;              // per test sample, its novelty score (empty without calibration)
  std::vector<bool> test_novel;                  // flagged at the model's quantile
  std::vector<double> novelty_class_thresholds;  // per class (model order), at the model's quantile; empty without calibration
  double novelty_threshold = 0;                  // the largest of them; 0 without calibration
  double novelty_quantile = 0;
  int novelty_folds = 0;                         // the calibration's folds (0: leave-one-out)
};

struct NestedCvOptions {
  int outer_folds = 5;     // capped at the smallest class size
  int repeats = 2;
  int inner_splits = 5;    // StratifiedShuffleSplit of each outer training fold for the inner grid search
  double validation_fraction = 0.2;
  GridSearchOptions grid;
  SearchMethod search = SearchMethod::Grid;  // the inner search (the main search's: Grid or Halving)
  HalvingOptions halving;
  std::uint64_t seed = 45;
};

// Nested, repeated stratified CV on unscaled features X (one row per sample), classes y in 0..k-1: the whole
// selection (z-score fitted on the outer training fold, inner grid search) runs inside each outer fold.
// An outer fold too small for its inner split is skipped (the fold count says so).
NestedCvResult nested_cross_validation(const Eigen::MatrixXd& X, const std::vector<int>& y,
                                       const NestedCvOptions& options);

struct TrainingResult {
  ClassifierModel model;
  TrainingReport report;
};

// Throws InvalidInputError("training_data") for too few samples / classes, inconsistent feature sizes;
// InvalidInputError("training_losses") when a class lost more than options.loss_policy allows.
TrainingResult train_classifier(const std::vector<TrainingSample>& samples, const TrainOptions& options);

// The feature matrix (unscaled, one row per sample) and class indices (classes sorted by name).
void build_feature_matrix(const std::vector<TrainingSample>& samples, const FeatureSpec& spec, Eigen::MatrixXd& X,
                          std::vector<int>& y, std::vector<std::string>& classes);

// SHA-256 over labels and feature values in a canonical text form (not file names: paths differ per machine).
std::string dataset_sha256(const std::vector<TrainingSample>& samples);

}  // namespace wish
