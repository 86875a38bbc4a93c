// `wish train INPUT`: trains an RBF C-SVM classifier as in paper §6 (docs/design/classification.md) and writes the model
// file, a JSON report, a printed table and an SVG heat map of the grid. INPUT is
//   * a directory with one sub-directory per class holding meshes (OBJ, PLY, OFF, STL) and/or label volumes
//     (NIfTI-1, TIFF; format by content): every kept object of a volume in class folder C is a sample of class C,
//     id "<volume>#<label id>"; the volume options (--spacing, --min-voxels, --drop-truncated, ...) are mesh-labels', or
//   * a CSV manifest "path,label[,label_id]" (relative paths against the manifest's directory; a row with a label
//     id names one object of a volume, with its own class), or
//   * a descriptor CSV from `wish describe --csv` / `wish train --save-descriptors` (has xi_0.. columns), with a
//     label column or labels joined from --labels MANIFEST — so a grid search need not redo the flows.
// The command line makes one DescriptorRecipe (map method and options, SH fit, feature pipeline, off-recipe
// policy) that describes every mesh and is stored in the model. Meshes are described in parallel (progress on
// stderr); a mesh that fails, or whose map came from another method than the recipe's while the policy refuses
// that, is lost: losses are counted per class and error code in the report and on stdout, and training stops
// when a class loses more than --max-class-loss of its meshes (unless --allow-losses). When the global descriptors are available, accuracies with xi alone, global alone and
// combined are printed side by side.
// The driver itself (gathering, the descriptor CSV's fallbacks and checks, training, the comparison) is core's
// run_training (core/training/training_run.hpp); this file maps the options to its request and prints its result.
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/command_registry.hpp"
#include "cli/enum_option.hpp"
#include "cli/volume_options.hpp"
#include "core/classify/default_recipe.hpp"
#include "core/classify/feature_pipeline.hpp"
#include "core/classify/laplace_spectrum.hpp"
#include "core/classify/recipe_names.hpp"
#include "core/common/errors.hpp"
#include "core/sh/sh_fit_names.hpp"
#include "core/sh/sh_lmax_range.hpp"
#include "core/spherical_map/map_types.hpp"
#include "core/training/dataset.hpp"
#include "core/training/descriptor_table.hpp"
#include "core/training/grid_search.hpp"
#include "core/training/training.hpp"
#include "core/training/training_report.hpp"
#include "core/training/training_run.hpp"
#include "wire/training_report_json.hpp"

namespace wish::cli::train_command {  // one namespace per command: the commands compile in one unity batch
namespace {

const DescriptorRecipe kDefaults = default_training_recipe();

struct TrainCliOptions {
  std::string input, labels, out = "model.json", report, heatmap, save_descriptors, name = "wish-svm";
  // The recipe's defaults are core's one value (core/classify/default_recipe.hpp: what they are and why).
  int lmax = kDefaults.sh.lmax;
  FeatureFamily features = kDefaults.features.family;
  ScaleNormalization scale = kDefaults.features.scale;
  int spectrum_count = kDefaultSpectrumCount;
  bool log = kDefaults.features.log_transform, global_scale_free = false, refit_all = false, no_compare = false, quiet = false;
  bool early_stop = true;
  SearchMethod search = SearchMethod::Auto;
  double novelty_quantile = 0.99;
  int novelty_folds = 0;
  NoveltyRule novelty_rule = NoveltyRule::NearestClass;
  std::uint64_t seed = 42;
  int jobs = 0;
  MapMethod method = kDefaults.map.method;
  FitWeighting weights = kDefaults.sh.weighting;
  FitSolver solver = FitSolver::Direct;
  std::string area_correction = "none";
  std::string canonical = to_string(kDefaults.map.canonical.method);
  std::string sampling = to_string(kDefaults.sh.sampling);
  double regularization = kDefaults.sh.regularization;
  double test_fraction = 0.2;
  OffRecipePolicy off_recipe = kDefaults.off_recipe;
  bool no_fallback = false, allow_losses = false;
  double max_class_loss = 0.1;
  int grid_splits = 10, nested_repeats = 2, nested_folds = 5;
  std::vector<int> c_range{-2, 10}, gamma_range{-9, 3};
  VolumeCliOptions volume;
};


void print_progress(const std::string& line, bool lost, bool quiet) {
  if (!quiet || lost) std::cerr << line << "\n";
}

CommandRunner setup_train(CLI::App& sub) {
  auto o = std::make_shared<TrainCliOptions>();
  sub.add_option("input", o->input,
                 "Class directory tree (meshes or label volumes), manifest CSV (path,label[,label_id]) or descriptor CSV")
      ->required();
  sub.add_option("--labels", o->labels, "Manifest CSV (path,label) giving the labels of a descriptor CSV");
  // Core's bounds (issue 37 item 5): features start at degree 1, the SH fit stops at kShMaxFitLmax.
  sub.add_option("--lmax", o->lmax, "Use xi(1..Lmax); meshes are described with this Lmax")
      ->check(CLI::Range(kMinFeatureLmax, kShMaxFitLmax))->capture_default_str();
  CLI::Option* features_option = add_enum_option(sub, "--features", o->features, kFeatureFamilyNames, "Feature family");
  sub.add_option("--spectrum-count", o->spectrum_count,
                 "Families with the spectrum: how many Laplace-Beltrami eigenvalues (ShapeDNA)")
      ->check(CLI::Range(1, kMaxSpectrumCount))->capture_default_str();
  add_enum_option(sub, "--scale", o->scale, kScaleNormalizationNames,
                  "Scale normalisation of xi: none, xi(l)/xi(1) or xi(l)/surface area");
  sub.add_flag("--log,!--no-log", o->log, "log of the (normalised) energies (default on; --no-log: off)");
  sub.add_flag("--global-scale-free", o->global_scale_free, "Only the scale-free global descriptors");
  sub.add_option("--seed", o->seed, "Seed of splits and Platt calibration")->capture_default_str();
  sub.add_option("--jobs", o->jobs, "Threads (0: all cores)")->capture_default_str();
  sub.add_option("--out", o->out, "Model file to write")->capture_default_str();
  sub.add_option("--report", o->report, "JSON report to write");
  sub.add_option("--heatmap", o->heatmap, "SVG heat map of the grid accuracy to write");
  sub.add_option("--save-descriptors", o->save_descriptors, "Write the labelled descriptors (CSV) for re-training");
  sub.add_option("--name", o->name, "Model name")->capture_default_str();
  add_enum_option(sub, "--method", o->method, kMapMethodNames, "Spherical map method of the recipe");
  sub.add_option("--area-correction", o->area_correction,
                 "Area-aware correction after the conformal map, part of the recipe: none (the paper's map) | "
                 "density_equalizing (beyond the paper)")
      ->check(CLI::IsMember({"none", "density_equalizing", "dem"}))->capture_default_str();
  sub.add_option("--canonical", o->canonical,
                 "The map the descriptor is computed on: isometric (the canonical map, relaxed from whichever map the "
                 "chain found: one definition for every mesh, issue 37) | none (the chain's own map)")
      ->check(CLI::IsMember({"none", "isometric"}))->capture_default_str();
  sub.add_option("--sampling", o->sampling,
                 "Where the SH fit samples the surface: surface (quadrature over every face: independent of the "
                 "triangulation) | vertices (the paper)")
      ->check(CLI::IsMember({"vertices", "surface"}))->capture_default_str();
  sub.add_flag("--no-fallback", o->no_fallback, "Do not try other attempts/methods when the recipe's map fails");
  add_enum_option(sub, "--off-recipe", o->off_recipe, kOffRecipePolicyNames,
                  "Policy for maps made by another method than --method (a fallback): refuse (the mesh is lost in "
                  "training, a classify request gets 422 off_recipe) | accept_flagged (kept, flagged recipe_match false)");
  sub.add_option("--max-class-loss", o->max_class_loss,
                 "Stop when any class loses more than this share of its meshes (refused or failed)")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  sub.add_flag("--allow-losses", o->allow_losses, "Report lost meshes but train whatever a class lost");
  add_enum_option(sub, "--weights", o->weights, kFitWeightingNames, "SH fit weights");
  add_enum_option(sub, "--solver", o->solver, kFitSolverNames, "SH fit solver");
  sub.add_option("--regularization", o->regularization, "SH fit regularisation nu (paper units; the fit uses nu/10^4 at unit-sum weights)")->capture_default_str();
  sub.add_option("--test-fraction", o->test_fraction, "Stratified hold-out fraction")->check(CLI::Range(0.05, 0.5))->capture_default_str();
  sub.add_option("--grid-splits", o->grid_splits, "StratifiedShuffleSplit splits per grid cell")->check(CLI::Range(1, 100))->capture_default_str();
  sub.add_option("--nested-repeats", o->nested_repeats, "Repeats of the nested CV (0: skip)")->check(CLI::Range(0, 100))->capture_default_str();
  sub.add_option("--nested-folds", o->nested_folds, "Outer folds of the nested CV")->check(CLI::Range(2, 20))->capture_default_str();
  sub.add_option("--c-range", o->c_range, "log10 of the first and last C")->expected(2)->capture_default_str();
  sub.add_option("--gamma-range", o->gamma_range, "log10 of the first and last gamma")->expected(2)->capture_default_str();
  sub.add_flag("--early-stop,!--no-early-stop", o->early_stop,
               "Grid search: stop a gamma row, C ascending, at the first C past its peak (once the row has risen, "
               "a C whose mean validation accuracy is not above the row's best; default on; --no-early-stop: every "
               "cell)");
  add_enum_option(sub, "--search", o->search, kSearchMethodNames,
                  "auto: the full grid up to " + std::to_string(ScalePolicy{}.halving_above_rows) +
                      " training rows, successive halving above (see below); grid / halving: that search at any size");
  sub.add_option("--novelty-quantile", o->novelty_quantile,
                 "The model's default novelty threshold: per class, this quantile of the class's leave-one-out (or "
                 "--novelty-folds cross-validated) k-NN distances (a prediction above every class's says novel: true; predict/serve may override)")
      ->check(CLI::Range(0.5, 0.999999))->capture_default_str();
  add_enum_option(sub, "--novelty-rule", o->novelty_rule, kNoveltyRuleNames,
                  "Which class's threshold flags a sample novel: every class's (nearest_class, model format 5/6) or the "
                  "class the SVM predicts (predicted_class, format 7), or the nearest class in units of its median calibration "
                  "distance against one pooled threshold (median_scale, format 8); docs/accuracy.md \"Issue 38\"");
  sub.add_option("--novelty-folds", o->novelty_folds,
                 "Novelty calibration scores: 0 leave-one-out (model format 5), N >= 2 N-fold cross-validated (format 6: "
                 "the quantile's false-flag rate holds more closely, fewer new types flagged; docs/benchmarks.md \"Novelty\")")
      ->check(CLI::Range(0, 100))
      ->check([](const std::string& v) { return v == "1" ? std::string("one fold is no calibration: 0 (leave-one-out) or at least 2") : std::string(); })
      ->capture_default_str();
  sub.add_flag("--refit-all", o->refit_all, "Refit the final model on all samples (default: on the training split)");
  sub.add_flag("--no-compare", o->no_compare, "Do not train the other feature families for comparison");
  sub.add_flag("--quiet", o->quiet, "Only failures on stderr");
  add_volume_options(sub, o->volume);
  sub.footer(
      "Defaults: the recipe chosen by classification accuracy and by the meshes it keeps (docs/accuracy.md,\n"
      "core/classify/default_recipe.hpp): " + recipe_summary(kDefaults) + ".\n"
      "With --canonical isometric every mesh the chain maps is kept: its descriptor is computed on the canonical map\n"
      "whichever attempt found the bijective start (a relaxation stopped by its budget is kept, reported as\n"
      "canonical_converged false). `wish describe` defaults to the paper's map and fit (willmore, nu 1e-5, Lmax 15)\n"
      "instead. A model records its recipe: classify uses it.\n"
      "\n" + training_scale_help(ScalePolicy{}));
  return [o, features_option]() {
    // Options -> request; the driver (core/training/training_run.hpp) gathers, checks, falls back and trains.
    TrainingRunRequest request;
    request.input = o->input;
    request.labels = o->labels;
    DescriptorRecipe& recipe = request.recipe;
    recipe.map.method = o->method;
    recipe.map.fallback = !o->no_fallback;
    recipe.map.area_correction.method = area_correction_from_name(o->area_correction);
    recipe.map.canonical.method = canonical_map_from_name(o->canonical);
    recipe.sh.sampling = fit_sampling_from_name(o->sampling);
    recipe.sh.lmax = o->lmax;
    recipe.sh.weighting = o->weights;
    recipe.sh.solver = o->solver;
    recipe.sh.regularization = o->regularization;
    recipe.features.family = o->features;
    recipe.features.l_min = kMinFeatureLmax;
    recipe.features.l_max = o->lmax;
    recipe.features.scale = o->scale;
    recipe.features.log_transform = o->log;
    recipe.features.global_scale_free = o->global_scale_free;
    // Only a family with the spectrum has a count: any other keeps the legacy 0 (no spectrum), so its model file is
    // the recipe version it was before issue 38 (descriptor_recipe_codec.hpp) and equal to the bundled model's.
    recipe.features.spectrum_count = family_blocks(o->features).spectrum ? o->spectrum_count : 0;
    recipe.off_recipe = o->off_recipe;
    request.family_chosen = features_option->count() > 0;
    request.describe.volume = to_volume_options(o->volume);
    request.describe_jobs = o->jobs;
    request.compare_families = !o->no_compare;

    TrainOptions& t = request.train;
    t.name = o->name;
    t.loss_policy.max_class_loss = o->max_class_loss;
    t.loss_policy.allow_losses = o->allow_losses;
    t.grid.Cs = decade_grid(o->c_range[0], o->c_range[1]);
    t.grid.gammas = decade_grid(o->gamma_range[0], o->gamma_range[1]);
    t.grid.jobs = o->jobs;
    t.grid.early_stop = o->early_stop;
    t.scale.search = o->search;
    t.novelty_quantile = o->novelty_quantile;
    t.novelty_folds = o->novelty_folds;
    t.novelty_rule = o->novelty_rule;
    t.grid_splits = o->grid_splits;
    t.test_fraction = o->test_fraction;
    t.nested_repeats = o->nested_repeats;
    t.nested_outer_folds = o->nested_folds;
    t.refit_on_all = o->refit_all;
    t.seed = o->seed;
    if (!o->quiet) t.progress = [](const std::string& line) { std::cerr << "  " << line << "\n"; };

    TrainingRunEvents& events = request.events;
    events.note = [](const std::string& line) { std::cerr << line << "\n"; };
    events.item_described = [quiet = o->quiet](const std::string& line, bool lost) { print_progress(line, lost, quiet); };
    events.samples_gathered = [o](const std::vector<TrainingSample>& samples) {
      if (o->save_descriptors.empty()) return;
      std::ofstream(o->save_descriptors) << write_descriptor_table(samples);
      std::cerr << "wrote descriptors to " << o->save_descriptors << "\n";
    };
    events.summary = [](const std::string& line) { std::cout << line << "\n"; };
    events.model_trained = [o](const TrainingResult& trained) { trained.model.save(o->out); };

    const TrainingRunResult run = run_training(std::move(request));
    const TrainingResult& result = run.trained;
    const FeatureSpec& trained_features = result.model.feature_spec();  // after the run's fallback, if it took one

    std::cout << training_report_table(result.report) << "\n";
    std::cout << "feature family comparison (same splits and seed):\n";
    std::cout << std::left << std::setw(12) << "features" << std::right << std::setw(6) << "dim" << std::setw(9) << "C"
              << std::setw(9) << "gamma" << std::setw(8) << "grid" << std::setw(8) << "test" << std::setw(18) << "nested CV"
              << "\n";
    for (const FamilyScore& row : run.families) {
      std::ostringstream cv;
      cv << std::fixed << std::setprecision(3) << row.nested_mean << " +- " << row.nested_std;
      std::cout << std::left << std::setw(12) << row.family << std::right << std::setw(6) << row.features
                << std::setw(9) << std::setprecision(1) << std::scientific << row.C << std::setw(9) << row.gamma
                << std::fixed << std::setprecision(3) << std::setw(8) << row.grid_score << std::setw(8)
                << row.test_accuracy << std::setw(18) << cv.str() << "\n";
      std::cout.unsetf(std::ios::floatfield);
    }
    std::cout << "model: " << o->out << " (" << result.model.classes().size() << " classes, sha256 "
              << result.model.payload_sha256().substr(0, 16) << "...)\n";
    if (!run.losses.empty() || !run.unlabelled.empty())
      std::cout << "skipped: " << run.losses.size() << " failed meshes, " << run.unlabelled.size()
                << " unlabelled rows (see stderr)\n";

    if (!o->report.empty()) {
      const nlohmann::json rep = wire::training_run_json(
          result.report, {o->input, o->out, result.model.payload_sha256(), run.families, run.losses, run.unlabelled});
      std::ofstream(o->report) << rep.dump(2) << "\n";
    }
    if (!o->heatmap.empty())
      std::ofstream(o->heatmap) << grid_heatmap_svg(result.report.grid, "WISH grid search (" +
                                                                            std::string(to_string(trained_features.family)) +
                                                                            ", Lmax " + std::to_string(trained_features.l_max) + ")");
    return kExitOk;
  };
}

const bool registered = register_command(
    {"train", "Train an RBF SVM classifier (grid search, test split, nested CV) from labelled meshes or descriptors",
     &setup_train, 50});

}  // namespace
}  // namespace wish::cli::train_command
