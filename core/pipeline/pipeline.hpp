#pragma once
// The one call that turns mesh bytes into a descriptor (and a prediction): read -> validate/repair ->
// spherical map -> SH fit -> invariants -> (classify). Used by the CLI and by the HTTP service alike.

#include <optional>
#include <string>
#include <string_view>

#include "core/classify/classifier_model.hpp"
#include "core/common/deadline.hpp"
#include "core/io/mesh_io.hpp"
#include "core/sh/sh_descriptor.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/validation/mesh_report.hpp"

namespace wish {

struct PipelineOptions {
  ReadOptions read;
  RepairOptions repair;
  SphericalMapOptions map;
  ShFitOptions sh;
  bool compute_global_features = false;
  int laplace_spectrum_count = 0;  // > 0: also the first n Laplace-Beltrami eigenvalues (ShapeDNA; features.laplace_spectrum)
  bool compute_canonical_sh = false;  // also the SH coefficients in the canonical frame (features.canonical_sh)
  int reconstruction_level = -1;   // >= 0: also evaluate the SH surface on an icosphere of this level (0..7)
  double novelty_quantile = 0;     // classify: the novelty flag's threshold quantile; <= 0: the model's own
};

struct StageTimings {  // seconds
  double read = 0, validate = 0, map = 0, fit = 0, classify = 0, total = 0;
};

struct PipelineResult {
  MeshFormat format = MeshFormat::Unknown;
  std::vector<std::string> read_notes;
  PreparedMesh prepared;             // reports before/after repair, repairs; prepared.mesh was mapped
  SphericalMapResult map;
  ShDescriptor sh;
  ShapeFeatures features;
  std::optional<Prediction> prediction;
  // With a prediction: whether the map was made the model's way (descriptor_recipe.hpp). recipe_match false
  // means the model's off-recipe policy accepted a fallback map, and the result says so.
  std::optional<RecipeConformance> recipe;
  std::optional<Mesh> reconstruction;
  StageTimings timings;
};

// Throws WishError: InvalidInput / UnsupportedFormat / TooLarge from reading, Unmappable ("genus_nonzero",
// ..., or "map_failed" with details.check) from validation and mapping, Timeout from the deadline.
PipelineResult describe_mesh_bytes(std::string_view bytes, const PipelineOptions& options,
                                   const Deadline& deadline = {});
PipelineResult describe_mesh(Mesh mesh, const PipelineOptions& options, const Deadline& deadline = {});

// The first stages of describe_mesh — repair/validation and the sphere map — with the same options and checks, so
// that `wish map` and `wish describe` (and every other caller) end on the same chain attempt for every mesh (issue
// 37: one place decides the chain). Throws as describe_mesh for an unmappable input; a map that failed
// verification is returned (map.ok() false), not thrown: the caller decides (describe_mesh refuses it).
struct MappedMesh {
  PreparedMesh prepared;  // reports before/after repair, repairs; prepared.mesh was mapped
  SphericalMapResult map;
  double validate_seconds = 0, map_seconds = 0;
};
MappedMesh map_mesh(Mesh mesh, const PipelineOptions& options, const Deadline& deadline = {});

// The pipeline options that compute a descriptor as `recipe` says (map, fit, global features when needed);
// reading, repair limits and reconstruction are taken from `base`.
PipelineOptions options_for_recipe(const DescriptorRecipe& recipe, PipelineOptions base = {});

// Describes with the model's recipe (options.map / options.sh are replaced by it), checks the map against the
// recipe, then predicts. Throws WishError(Unmappable, "off_recipe") when the map came from another method and
// the model's policy refuses that.
PipelineResult classify_mesh_bytes(std::string_view bytes, const ClassifierModel& model, PipelineOptions options,
                                   const Deadline& deadline = {});
// The classify step on an already described mesh (result.map, result.features): conformance check, the model's
// off-recipe policy, prediction. Sets result.recipe and result.prediction.
void classify_described(PipelineResult& result, const ClassifierModel& model, const PredictOptions& predict = {});

}  // namespace wish
