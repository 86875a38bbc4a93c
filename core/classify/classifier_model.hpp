#pragma once
// A trained WISH classifier (paper §6; docs/design/classification.md): the descriptor recipe it was
// trained with (descriptor_recipe.hpp: map, fit, feature pipeline, off-recipe policy), the feature pipeline, the z-score scaler, and an RBF C-SVM (libsvm) with Platt probabilities.
// One self-describing, versioned JSON model file holds all of it (model_file.cpp).

#include <filesystem>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include <optional>

#include "core/classify/descriptor_recipe.hpp"
#include "core/classify/novelty.hpp"

namespace wish {

// The raw, rotation-invariant features of one shape, before the model's feature pipeline.
struct ShapeFeatures {
  Eigen::VectorXd invariants;  // xi(0..Lmax)
  Eigen::VectorXd global;      // global_shape_descriptors(mesh)
  // Computed only when a recipe's family uses them (empty otherwise):
  Eigen::VectorXd laplace_spectrum;  // λ_1..λ_n · A/(4π), ascending (laplace_spectrum.hpp)
  Eigen::VectorXd canonical_sh;      // canonical real SH coefficients of degrees 1..Lmax, flattened as
                                     // canonical_sh_features(.., 1, Lmax) (core/sh/sh_canonical_frame.hpp)
};

struct Prediction {
  std::string label;
  std::vector<std::pair<std::string, double>> probabilities;  // one per class, in the model's class order
  double margin = 0;  // decision value of the winning class against the runner-up (libsvm one-vs-one)
  // How unlike the training set the sample is (novelty.hpp); empty when the model has no novelty calibration
  // (model files written before issue 25).
  std::optional<NoveltyAssessment> novelty;
};

struct PredictOptions {
  double novelty_quantile = 0;  // threshold quantile of the novelty flag; <= 0: the model's own (0.99 by default)
};

// The spectrum of one class of the training set, for comparing a new shape's xi(l) with it (the web page draws it).
// Convention: natural log of xi(l) for l = 1 .. Lmax of the recipe (xi(0) depends on translation), mean and
// standard deviation over the class's training samples; xi is floored at 1e-300 before the log so that an exact
// zero stays finite. exp(log_xi_mean) is the class's geometric-mean spectrum.
struct ClassSpectrum {
  std::string label;
  std::int64_t count = 0;
  std::vector<double> log_xi_mean;  // index k is l = k + 1
  std::vector<double> log_xi_std;
};

struct TrainingSummary {
  std::string dataset_sha256;
  std::string trained_at;          // ISO 8601 UTC
  std::int64_t samples = 0;
  double best_c = 0, best_gamma = 0;
  double grid_score = 0;           // mean validation accuracy of the best grid cell
  double test_accuracy = 0;        // stratified 20 % hold-out
  double nested_cv_mean = 0, nested_cv_std = 0;
  std::string notes;
  std::vector<ClassSpectrum> class_spectra;  // in the model's class order; empty in models trained before it existed
};

// The recipe as the model file stores it (payload.recipe), as JSON text: for model listings and reports.
std::string descriptor_recipe_json_text(const DescriptorRecipe& recipe);

class ClassifierModel {
 public:
  // 2: the descriptor recipe (map + fit + features + off-recipe policy) in payload.recipe. Version 1 files
  // (payload.descriptor + payload.features) load through a migration with policy accept_flagged, which is
  // what version-1 code did with fallback maps.
  // 3: payload.novelty (the novelty calibration, issue 25), one reference set. A model with it is written as
  // version 3, so a reader of versions 1..2 refuses it rather than silently ignoring the block; one without it
  // is still written as 2.
  // 4: payload.novelty per class (reference_classes, one list of leave-one-out scores per class; novelty.hpp).
  // Format-3 files keep loading and computing their one-set figure.
  // 5: payload.novelty.whitening (the within-class whitening of the novelty distance; novelty.hpp). Format-4
  // files keep loading and computing their Euclidean figure.
  // 6: payload.novelty.calibration_folds (the per-class scores are cross-validated, not leave-one-out; an option,
  // novelty.hpp). Prediction computes the same figure. Models with leave-one-out scores are still written as 5.
  // 7: payload.novelty.rule = "predicted_class" (novelty.hpp NoveltyRule: the class the SVM predicts decides;
  // issue 38); calibration_folds and whitening as format 6 (each only when used). Models with the nearest-class
  // rule are written as before (5 or 6). 8: payload.novelty.rule = "median_scale" (novelty.hpp; issue 38, second
  // pass), written only for that rule.
  static constexpr int kFormatVersion = 8;

  // Throws InvalidInputError("model_invalid" | "model_version", ...) with a clear message on a wrong version,
  // a truncated or edited file, or inconsistent sizes.
  static ClassifierModel load(const std::filesystem::path& path);
  static ClassifierModel from_json_text(const std::string& text);
  std::string to_json_text() const;
  void save(const std::filesystem::path& path) const;

  // Replays the feature pipeline and the scaler, then the SVM. The label is libsvm's one-vs-one vote winner
  // (as scikit-learn's SVC.predict), which can in rare ties differ from the most probable class.
  // Throws InvalidInputError("feature_mismatch") when `features` lack what the model needs.
  Prediction predict(const ShapeFeatures& features, const PredictOptions& options = {}) const;
  bool has_novelty() const;
  const NoveltyCalibration* novelty_calibration() const;  // nullptr without one

  const std::string& name() const;
  const std::string& version() const;
  const std::vector<std::string>& classes() const;
  const DescriptorRecipe& recipe() const;
  const FeatureSpec& feature_spec() const { return recipe().features; }
  const TrainingSummary& training_summary() const;
  bool needs_global_features() const { return recipe().needs_global_features(); }
  const std::string& payload_sha256() const;  // SHA-256 of the canonical payload (the file's seal)

  struct State;  // defined in classifier_model.cpp / svm_engine.cpp
  explicit ClassifierModel(std::shared_ptr<const State> state);

 private:
  std::shared_ptr<const State> state_;  // immutable, shared: copies are cheap and thread-safe to use
};

}  // namespace wish
