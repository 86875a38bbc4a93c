#include "core/training/training_run.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <utility>

#include "core/classify/feature_pipeline.hpp"
#include "core/common/errors.hpp"
#include "core/spherical_map/map_types.hpp"
#include "core/training/descriptor_table.hpp"
#include "core/training/training_losses.hpp"

namespace wish {
namespace {

namespace fs = std::filesystem;

// The samples of the input, before any check of the features.
struct GatheredSamples {
  std::vector<TrainingSample> samples;
  std::vector<MeshLoss> losses;
  std::vector<std::string> unlabelled;
  bool has_global = true;
  bool described_here = true;  // false: the descriptors came from a CSV
};

void tell(const TrainingRunEvents& events, const std::string& line) {
  if (events.note) events.note(line);
}

GatheredSamples describe_training_items(const std::vector<DatasetItem>& items, const TrainingRunRequest& request) {
  DescribeSetOptions d;
  d.jobs = request.describe_jobs;
  d.progress = request.events.item_described;
  TrainingSet set = describe_dataset(items, recipe_describer(request.recipe, request.describe), d);
  GatheredSamples out;
  out.samples = std::move(set.samples);
  out.losses = std::move(set.losses);
  return out;
}

// A descriptor CSV: its rows are the samples, its xi columns fix the fit's Lmax (recipe.sh.lmax is set to it).
GatheredSamples read_training_descriptors(const std::string& text, TrainingRunRequest& request) {
  std::map<std::string, std::string> labels;
  if (!request.labels.empty())
    for (const auto& [path, label] : read_manifest(read_input_file(request.labels), fs::path(request.labels).parent_path()))
      labels[path] = label;
  DescriptorTable table = read_descriptor_table(text, labels);
  GatheredSamples out;
  out.samples = std::move(table.samples);
  out.unlabelled = std::move(table.unlabelled);
  out.has_global = table.has_global;
  out.described_here = false;
  request.recipe.sh.lmax = table.lmax;  // the descriptors were fitted up to this Lmax: the model must say so
  // The features cannot use degrees the CSV does not have. (The texts name `wish train`'s options: it is the one
  // caller, and what the user must change is the flag.)
  if (request.recipe.features.l_max > table.lmax)
    throw InvalidInputError("training_data", "--lmax " + std::to_string(request.recipe.features.l_max) +
                                                 " exceeds the CSV's xi_" + std::to_string(table.lmax));
  tell(request.events, "read " + std::to_string(out.samples.size()) + " labelled descriptors (xi_0..xi_" +
                           std::to_string(table.lmax) + (out.has_global ? ", global descriptors" : "") + ") from " +
                           request.input + "; the model records the map/fit settings given on this command line");
  for (const auto& f : out.unlabelled) tell(request.events, "wish train: skipped " + f + ": no label");
  return out;
}

GatheredSamples gather_training_samples(TrainingRunRequest& request) {
  const fs::path input = request.input;
  if (fs::is_directory(input)) {
    const auto items = list_class_directories(input);
    if (items.empty())
      throw InvalidInputError("training_data", "no meshes or label volumes in class sub-directories of " + request.input);
    tell(request.events, "describing " + std::to_string(items.size()) + " files (Lmax " +
                             std::to_string(request.recipe.sh.lmax) + ", " + to_string(request.recipe.map.method) + ")");
    return describe_training_items(items, request);
  }
  const std::string text = read_input_file(request.input);
  const auto header = parse_csv(text.substr(0, text.find('\n') + 1));
  const bool descriptor_csv = !header.empty() && std::any_of(header[0].begin(), header[0].end(), [](const std::string& h) {
    return h == "xi_0";
  });
  if (descriptor_csv) return read_training_descriptors(text, request);
  const auto items = read_dataset_manifest(text, input.parent_path());
  tell(request.events, "describing " + std::to_string(items.size()) + " files from the manifest (Lmax " +
                           std::to_string(request.recipe.sh.lmax) + ")");
  return describe_training_items(items, request);
}

}  // namespace

TrainingRunResult run_training(TrainingRunRequest request) {
  const TrainingRunEvents& events = request.events;
  GatheredSamples gathered = gather_training_samples(request);
  for (const auto& f : gathered.losses) tell(events, "wish train: lost " + f.id + ": [" + f.code + "] " + f.message);
  if (!gathered.losses.empty()) {
    // Before training can stop on them; the report repeats the table (training_report_table).
    tell(events, std::to_string(gathered.losses.size()) + " of " +
                     std::to_string(gathered.samples.size() + gathered.losses.size()) +
                     " samples (meshes or volume objects) are NOT in the training set (refused or failed):\n" +
                     loss_table(summarize_training_set({gathered.samples, gathered.losses})));
  }
  if (events.samples_gathered) events.samples_gathered(gathered.samples);

  bool fell_back = false;
  std::optional<std::size_t> canonical_unconverged;
  DescriptorRecipe& recipe = request.recipe;
  if (!gathered.has_global && !request.family_chosen && recipe.needs_global_features()) {
    // A descriptor CSV of xi alone (written before --save-descriptors kept the global columns): the default family
    // cannot be built from it, the paper's can. Said, not silent; a chosen family still fails below.
    tell(events, "note: " + request.input + " has no global descriptors (g_* columns): training with features " +
                     to_string(FeatureFamily::Invariants) + " instead of the default " + to_string(recipe.features.family));
    recipe.features.family = FeatureFamily::Invariants;
    fell_back = true;
  }
  if (recipe.needs_global_features() && !gathered.has_global)
    throw InvalidInputError("training_data",
                            "--features " + std::string(to_string(recipe.features.family)) +
                                (recipe.features.scale == ScaleNormalization::ByArea ? " / --scale area" : "") +
                                " needs the global descriptors (g_* columns); train from meshes or a "
                                "CSV written by --save-descriptors");

  const std::vector<TrainingSample>& samples = gathered.samples;
  tell(events, "training on " + std::to_string(samples.size()) + " samples, features " +
                   to_string(recipe.features.family));
  if (gathered.described_here && recipe.map.canonical.method != CanonicalMap::None) {
    // A relaxation its budget stopped is kept (the recipe's descriptor of that mesh), so the count is told, not hidden.
    const auto unconverged = static_cast<std::size_t>(
        std::count_if(samples.begin(), samples.end(), [](const TrainingSample& s) { return s.canonical_unconverged; }));
    canonical_unconverged = unconverged;
    if (events.summary)
      events.summary("canonical map: " + std::to_string(samples.size() - unconverged) + " of " +
                     std::to_string(samples.size()) + " relaxations converged; " + std::to_string(unconverged) +
                     " stopped by their budget or step cap (kept: the recipe's descriptor, reported per mesh)");
  }

  TrainOptions& t = request.train;
  t.recipe = recipe;
  t.losses = gathered.losses;
  TrainingResult trained = train_classifier(samples, t);
  if (events.model_trained) events.model_trained(trained);

  std::vector<FamilyScore> families =
      gathered.has_global && request.compare_families
          ? compare_feature_families(samples, t, trained.report,
                                     [&events](const std::string& family) {
                                       tell(events, "comparison: training with features " + family);
                                     })
          : std::vector<FamilyScore>{family_score(to_string(recipe.features.family), trained.report)};
  const std::size_t sample_count = samples.size();
  return {std::move(trained),     std::move(families), std::move(gathered.losses), std::move(gathered.unlabelled),
          sample_count,           gathered.has_global, fell_back,                  canonical_unconverged};
}

}  // namespace wish
