#include "core/training/training_set.hpp"

#include <chrono>
#include <fstream>
#include <map>
#include <iomanip>
#include <sstream>

#include "core/common/errors.hpp"
#include "core/pipeline/volume_description.hpp"

namespace wish {

std::string read_input_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("file_not_found", "cannot open '" + path + "'", {{"file", path}});
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

namespace {

// The recipe's check on a described mesh: a sample, or a thrown WishError("off_recipe") under the refuse policy.
TrainingSample sample_of(const PipelineResult& r, const DescriptorRecipe& recipe, const std::string& id,
                         const std::string& label) {
  const RecipeConformance conformance = check_recipe(recipe, r.map);
  enforce_recipe_policy(recipe, conformance, "being trained");
  TrainingSample s;
  s.off_recipe = !conformance.match;
  s.canonical_unconverged = conformance.canonical != CanonicalMap::None && !conformance.canonical_converged;
  s.id = id;
  s.label = label;
  s.features = r.features;
  return s;
}

ItemDescription describe_mesh_item(const DatasetItem& item, const std::string& bytes, const DescriptorRecipe& recipe,
                                   PipelineOptions po) {
  const auto dot = item.path.find_last_of('.');
  if (dot != std::string::npos) po.read.hint = format_from_name(item.path.substr(dot));
  const PipelineResult r = describe_mesh_bytes(bytes, po);
  ItemDescription d;
  d.samples.push_back(sample_of(r, recipe, item.path, item.label));
  std::ostringstream st;
  st << "ok (" << std::fixed << std::setprecision(2) << r.timings.total << " s, " << to_string(r.map.method_used) << ")";
  if (d.samples.back().off_recipe) st << " OFF-RECIPE, kept (accept_flagged)";
  if (d.samples.back().canonical_unconverged)
    st << " canonical map not converged (" << to_string(r.map.canonical.stop) << ", E " << std::setprecision(4)
       << r.map.canonical.energy << "), kept";
  d.status = st.str();
  return d;
}

// A label volume: one sample per kept object (all of them, or the manifest's label ids with their classes). An
// object whose surface was refused, or whose description failed, is a loss with its reason; a label id the
// manifest names that is not among the kept objects is a loss "label_not_kept".
ItemDescription describe_volume_item(const DatasetItem& item, const std::string& bytes, const DescriptorRecipe& recipe,
                                     const PipelineOptions& po, VolumeOptions vo) {
  if (!item.object_labels.empty()) {
    vo.objects.label_ids.clear();
    for (const auto& [id, label] : item.object_labels) vo.objects.label_ids.push_back(id);
  }
  ItemDescription d;
  std::map<std::uint32_t, bool> seen;
  const auto start = std::chrono::steady_clock::now();
  // Only the manifest's ids are asked for (the id filter keeps only these; an object it would not name is skipped).
  const auto asked = [&](std::uint32_t id) { return item.object_labels.empty() || item.object_labels.count(id) > 0; };
  const VolumeSummary summary = describe_volume(
      bytes, vo,
      [&](const volume::VolumeObject& object, Mesh mesh) -> std::optional<PipelineResult> {
        if (!asked(object.id)) return std::nullopt;
        return describe_mesh(std::move(mesh), po);
      },
      [&](std::size_t, VolumeObjectResult& object) {
        if (!asked(object.object.id)) return;
        const std::string id = item.path + "#" + std::to_string(object.object.id);
        std::string label = item.label;
        if (!item.object_labels.empty()) {
          label = item.object_labels.at(object.object.id);
          seen[object.object.id] = true;
        }
        // A refused surface or a failed description: a loss with the object's error (code and message).
        if (!object.ok()) {
          d.losses.push_back({id, label, object.error->code(), object.error->what()});
          return;
        }
        try {
          d.samples.push_back(sample_of(*object.result, recipe, id, label));
        } catch (const WishError& e) {  // off_recipe under the refuse policy
          d.losses.push_back({id, label, e.code(), e.what()});
        }
      });
  for (const auto& [id, label] : item.object_labels)
    if (!seen.count(id))
      d.losses.push_back({item.path + "#" + std::to_string(id), label, "label_not_kept",
                          "label id " + std::to_string(id) + " is not among the volume's kept objects (absent, fewer "
                          "voxels than the minimum or a speck, or touching the border while truncated objects are dropped)"});
  int flagged = 0;
  for (const auto& s : d.samples) flagged += s.off_recipe;
  std::ostringstream st;
  st << summary.kept << " objects (" << summary.found << " found; dropped " << summary.dropped_specks << " specks, "
     << summary.dropped_small << " small, "
     << summary.dropped_truncated << " truncated, " << summary.dropped_not_selected << " not selected; "
     << summary.fragments_merged << " fragments merged): "
     << d.samples.size() << " described, " << d.losses.size() << " lost; input " << volume::to_string(summary.input.kind);
  if (summary.input.threshold) st << " thresholded at " << *summary.input.threshold;
  for (const auto& w : summary.input.warnings) st << "; WARNING: " << w;
  if (flagged) st << ", " << flagged << " OFF-RECIPE kept (accept_flagged)";
  st << " (" << std::fixed << std::setprecision(1)
     << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s)";
  d.status = st.str();
  return d;
}

}  // namespace

ItemDescriber recipe_describer(const DescriptorRecipe& recipe, const TrainingDescribeOptions& options) {
  PipelineOptions po = options_for_recipe(recipe, options.base);
  po.compute_global_features = true;  // for the feature family comparison
  return [recipe, po, options](const DatasetItem& item) {
    // A zarr store directory arrives as its zip (core/io/volume_io.hpp read_volume_input), like an upload.
    const std::string bytes = is_zarr_directory(item.path) ? read_zarr_directory(item.path, options.volume.read)
                                                           : read_input_file(item.path);
    if (detect_volume_format(bytes) != VolumeFormat::Unknown)  // by content, not by name
      return describe_volume_item(item, bytes, recipe, po, options.volume);
    if (!item.object_labels.empty())
      throw InvalidInputError("invalid_manifest", "'" + item.path + "' is listed with label ids but is not a label volume "
                                          "(NIfTI-1 or TIFF)", {{"file", item.path}});
    return describe_mesh_item(item, bytes, recipe, po);
  };
}

}  // namespace wish
