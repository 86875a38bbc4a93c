#pragma once
// The training driver's data side (issue 16 item 3; used by `wish train`, and meant for the service and the batch
// runner): find a labelled dataset (class folders or a manifest), describe every item in parallel with one
// describer (one compute thread per worker: core/common/thread_policy.hpp), collect what did not become a sample as
// losses (training_losses.hpp: never dropped silently), and compare the feature families (xi alone, global alone,
// combined) on the same samples, splits and seed.
// An item is a file: a mesh (one sample) or a label volume (one sample per kept object). The describer that turns
// an item into samples is a separate file (core/training/training_set.hpp, on top of the pipeline), so this file
// does not depend on the map or the readers.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/training/training.hpp"
#include "core/training/training_losses.hpp"

namespace wish {

struct DatasetItem {
  std::string path;   // file (mesh or label volume)
  std::string label;  // class of every sample made from the file (when object_labels is empty)
  // Label volumes listed by object in a manifest (path,label,label_id): only these objects, each with its class.
  std::map<std::uint32_t, std::string> object_labels;
};

// Files a class folder may hold as training inputs, by name: meshes (.obj .ply .off .stl, any case) and label
// volumes (core/io/volume_io.hpp is_volume_file_name: .nii .nii.gz .tif .tiff .zarr.zip, and OME-Zarr store
// directories). The content decides the format
// later; other files (README, CSV) are ignored.
bool is_mesh_file_name(const std::filesystem::path& path);

// One item per input file of each sub-directory of `root`; the sub-directory's name is the class. Classes and
// files sorted by name (deterministic). Sub-directories without inputs are skipped.
std::vector<DatasetItem> list_class_directories(const std::filesystem::path& root);

// A manifest CSV "path,label[,label_id]" (header optional: path|file,label|class[,label_id]); relative paths are
// resolved against `base`. Rows with a label id name one object of a label volume; rows of the same file with
// label ids become one item (the volume is read once). Throws InvalidInputError("invalid_manifest") naming the line.
std::vector<DatasetItem> read_dataset_manifest(const std::string& csv_text, const std::filesystem::path& base);

// What one item gave: samples (with their labels) and losses (a mesh, an object, or the whole file when it could
// not be read), and a one-line status for the progress line.
struct ItemDescription {
  std::vector<TrainingSample> samples;
  std::vector<MeshLoss> losses;
  std::string status;
};
using ItemDescriber = std::function<ItemDescription(const DatasetItem& item)>;

struct DescribeSetOptions {
  int jobs = 0;  // worker threads over items (0: hardware concurrency), each limited to one compute thread
  // Called (serialised) once per item with "[n/N, t s] path: status"; `lost` tells whether the item lost anything.
  std::function<void(const std::string& line, bool lost)> progress;
};

struct TrainingSet {
  std::vector<TrainingSample> samples;  // in item order
  std::vector<MeshLoss> losses;         // in item order
};

// Describes every item with `describe` on `jobs` workers. A WishError thrown by the describer becomes a loss of the
// whole item (its code and message); other exceptions propagate.
TrainingSet describe_dataset(const std::vector<DatasetItem>& items, const ItemDescriber& describe,
                             const DescribeSetOptions& options = {});

// The per-class loss table of a set (summarize_losses over kept, lost and flagged samples).
std::vector<ClassLosses> summarize_training_set(const TrainingSet& set);

// One row of the feature family comparison.
struct FamilyScore {
  std::string family;  // "invariants" | "global" | "combined"
  std::size_t features = 0;
  double C = 0, gamma = 0, grid_score = 0, test_accuracy = 0, nested_mean = 0, nested_std = 0;
  std::vector<double> nested_scores, nested_inner_scores;  // per outer fold (the same folds for every family)
};

FamilyScore family_score(const std::string& family, const TrainingReport& report);

// The trained model's family first (from `trained`), then each other family trained on the same samples with
// the same options (splits, seed, grid); options.progress is not called for them. `on_family` (optional) is told
// before each extra training.
std::vector<FamilyScore> compare_feature_families(const std::vector<TrainingSample>& samples, const TrainOptions& options,
                                                  const TrainingReport& trained,
                                                  const std::function<void(const std::string& family)>& on_family = {});

}  // namespace wish
