#pragma once
// The training driver of `wish train` (issue 37 item 5): one labelled input in, a trained model, its report and the
// feature family comparison out. It lives in core, not in the CLI, so that the recipe's checks and fallbacks are
// core's (one place, testable without the executable); the CLI maps its options to a request and prints the result.
// It sits in the training area (above pipeline; the service does not link it) because it needs the pipeline's
// describer (training_set.hpp).
//
// The input is one of
//   * a directory with one sub-directory per class holding meshes and/or label volumes (list_class_directories);
//   * a descriptor CSV (`wish describe --csv`, `wish train --save-descriptors`: it has an xi_0 column), labelled by
//     its own label column or by a manifest "path,label" (`labels`), so a grid search need not redo the maps;
//   * a dataset manifest CSV "path,label[,label_id]" (read_dataset_manifest).
// Meshes and volumes are described with the request's recipe; a descriptor CSV brings its descriptors, fitted to its
// own Lmax, which the model then records (the map and fit settings recorded are the request's).
//
// Nothing is dropped silently: what is read, skipped, lost and fallen back to is told through events.note as it
// happens, and the losses and unlabelled rows are in the result.
//
// Throws InvalidInputError("training_data") for an empty class directory, a requested Lmax above a descriptor CSV's
// xi columns, or a feature family that needs the global descriptors (g_* columns) a descriptor CSV does not have;
// IoError("file_not_found") for an input that cannot be read; whatever describe_dataset, train_classifier
// (e.g. "training_losses") and compare_feature_families throw.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/classify/descriptor_recipe.hpp"
#include "core/training/dataset.hpp"
#include "core/training/training.hpp"
#include "core/training/training_set.hpp"

namespace wish {

// How the run reports while it runs; every member is optional.
struct TrainingRunEvents {
  // A log line (may hold several lines, no trailing newline): what was read, skipped or lost, the fallback taken,
  // what is trained next. `wish train` prints them on stderr.
  std::function<void(const std::string& line)> note;
  // One line per described item (describe_dataset's progress); `lost`: the item lost a mesh or object.
  std::function<void(const std::string& line, bool lost)> item_described;
  // Once the samples are gathered and the losses told, before the features are checked and training starts (e.g. to
  // save the descriptors for a later run: they are saved even when training then refuses them).
  std::function<void(const std::vector<TrainingSample>& samples)> samples_gathered;
  // A line of the run's outcome told before training (the canonical map's convergence count); stdout in `wish train`.
  std::function<void(const std::string& line)> summary;
  // The model is trained, before the other families are compared (e.g. to save it: it exists even if the slower
  // comparison is interrupted).
  std::function<void(const TrainingResult& trained)> model_trained;
};

struct TrainingRunRequest {
  std::string input;   // class directory, descriptor CSV or dataset manifest CSV
  std::string labels;  // descriptor CSV only: manifest "path,label" giving its rows' labels; empty: its label column
  // How meshes are described and the features built. recipe.features.l_max is the requested Lmax (features
  // xi(l_min..l_max)); with a descriptor CSV recipe.sh.lmax becomes the CSV's.
  DescriptorRecipe recipe;
  // False: a descriptor CSV without the global descriptors cannot build a recipe family that needs them, so the run
  // trains the invariants family instead, and says so (note). True (the user chose the family): such a CSV is refused.
  bool family_chosen = false;
  TrainingDescribeOptions describe;  // reading limits and, for label volumes, the volume options
  int describe_jobs = 0;             // workers over the items (0: hardware concurrency)
  // Grid, splits, seed, loss policy, novelty, training progress. train.recipe and train.losses are the run's: the
  // recipe above (after any fallback) and the losses of the description.
  TrainOptions train;
  bool compare_families = true;  // train the other feature families too (needs the global descriptors)
  TrainingRunEvents events;
};

struct TrainingRunResult {
  TrainingResult trained;               // the model (its recipe: the one trained, fallback included) and the report
  std::vector<FamilyScore> families;    // the trained family first; others only when compared
  std::vector<MeshLoss> losses;         // meshes, objects or files that did not become samples
  std::vector<std::string> unlabelled;  // descriptor CSV rows without a label (skipped)
  std::size_t samples = 0;              // samples trained on
  bool has_global = true;               // false: a descriptor CSV without the g_* columns
  bool fell_back_to_invariants = false;  // the family was switched for want of the global descriptors
  // Described here with a canonical map: the relaxations stopped by their budget or step cap (kept, their samples
  // flagged canonical_unconverged). Empty otherwise (no canonical map, or a descriptor CSV).
  std::optional<std::size_t> canonical_unconverged;
};

TrainingRunResult run_training(TrainingRunRequest request);

}  // namespace wish
