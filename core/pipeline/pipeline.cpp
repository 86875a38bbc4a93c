// The WISH pipeline (paper Fig. 1): read -> validate/repair -> conformal sphere map (§4) -> SH fit (§5)
// -> rotation-invariant energies (Eq. 14) -> SVM (§6). Every stage is timed; every failure is a WishError
// with a machine-readable code, so the CLI and the HTTP service report it the same way.
#include "core/pipeline/pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

#include "core/classify/global_descriptors.hpp"
#include "core/classify/laplace_spectrum.hpp"
#include "core/common/elapsed.hpp"
#include "core/sh/sh_canonical_frame.hpp"
#include "core/common/stage_profile.hpp"
#include "core/sh/sh_fit.hpp"
#include "core/sh/sh_reconstruction.hpp"

namespace wish {
namespace {

using Clock = std::chrono::steady_clock;

// A map that failed verification is never passed on as a success (docs/design/spherical-map.md §7).
void require_verified_map(const SphericalMapResult& map) {
  if (map.ok()) return;
  const MapAttempt* last = map.attempts.empty() ? nullptr : &map.attempts.back();
  std::string message = std::string("the spherical map failed verification (") + to_string(map.failed_check) + ")";
  if (last && !last->message.empty()) message += ": " + last->message;
  message += " after " + std::to_string(map.attempts.size()) + " attempt(s)";
  throw WishError(ErrorCategory::Unmappable, "map_failed", message,
                  {{"check", std::string(to_string(map.failed_check))},
                   {"status", std::string(to_string(map.status))},
                   {"attempts", static_cast<std::int64_t>(map.attempts.size())},
                   {"flipped_faces", static_cast<std::int64_t>(map.quality.flipped_faces)},
                   {"roundness", map.quality.roundness}});
}

}  // namespace

MappedMesh map_mesh(Mesh mesh, const PipelineOptions& options, const Deadline& deadline) {
  MappedMesh out;
  auto t = Clock::now();
  {
    const profile::ScopedStage stage("prepare");
    out.prepared = prepare_for_mapping(std::move(mesh), options.repair);
  }
  require_mappable(out.prepared);
  out.validate_seconds = seconds_since(t);
  deadline.check("validation");

  t = Clock::now();
  out.map = compute_spherical_map(out.prepared.mesh, options.map, deadline);
  out.map_seconds = seconds_since(t);
  return out;
}

PipelineResult describe_mesh(Mesh mesh, const PipelineOptions& options, const Deadline& deadline) {
  const auto start = Clock::now();
  PipelineResult result;
  MappedMesh mapped = map_mesh(std::move(mesh), options, deadline);
  result.prepared = std::move(mapped.prepared);
  result.map = std::move(mapped.map);
  result.timings.validate = mapped.validate_seconds;
  result.timings.map = mapped.map_seconds;
  require_verified_map(result.map);
  deadline.check("spherical map");

  const auto t = Clock::now();
  const profile::ScopedStage fit_stage("sh.fit+invariants");
  result.sh = fit_spherical_harmonics(result.prepared.mesh, result.map.sphere, options.sh);
  result.features.invariants = result.sh.invariants;
  if (options.compute_global_features) result.features.global = global_shape_descriptors(result.prepared.mesh);
  if (options.compute_canonical_sh) {
    const CanonicalShFrame frame = canonical_sh_frame(result.sh, result.prepared.mesh);
    result.features.canonical_sh = canonical_sh_features(frame.coefficients, 1, result.sh.lmax);
  }
  if (options.laplace_spectrum_count > 0)
    result.features.laplace_spectrum = laplace_spectrum(result.prepared.mesh, options.laplace_spectrum_count).values;
  if (options.reconstruction_level >= 0)
    result.reconstruction = reconstruct_on_icosphere(result.sh, options.reconstruction_level);
  result.timings.fit = seconds_since(t);

  result.timings.total = seconds_since(start);
  return result;
}

PipelineResult describe_mesh_bytes(std::string_view bytes, const PipelineOptions& options, const Deadline& deadline) {
  const auto start = Clock::now();
  ReadResult read = [&] {
    const profile::ScopedStage stage("io.read");
    return read_mesh(bytes, options.read);
  }();
  const double read_seconds = seconds_since(start);
  deadline.check("reading");

  PipelineResult result = describe_mesh(std::move(read.mesh), options, deadline);
  result.format = read.format;
  result.read_notes = std::move(read.notes);
  result.timings.read = read_seconds;
  result.timings.total = seconds_since(start);
  return result;
}

PipelineOptions options_for_recipe(const DescriptorRecipe& recipe, PipelineOptions base) {
  base.map = recipe.map;
  // Another method's map would be refused, unless the canonical map is computed from whichever start.
  base.map.prefer_method = recipe.off_recipe == OffRecipePolicy::Refuse && recipe.map.canonical.method == CanonicalMap::None;
  base.sh = recipe.sh;
  base.compute_global_features = base.compute_global_features || recipe.needs_global_features();
  if (recipe.needs_laplace_spectrum())
    base.laplace_spectrum_count = std::max(base.laplace_spectrum_count, recipe.features.spectrum_count);
  base.compute_canonical_sh = base.compute_canonical_sh || recipe.needs_canonical_sh();
  return base;
}

void classify_described(PipelineResult& result, const ClassifierModel& model, const PredictOptions& predict) {
  const RecipeConformance conformance = check_recipe(model.recipe(), result.map);
  enforce_recipe_policy(model.recipe(), conformance, model.name());
  result.recipe = conformance;
  result.prediction = model.predict(result.features, predict);
}

PipelineResult classify_mesh_bytes(std::string_view bytes, const ClassifierModel& model, PipelineOptions options,
                                   const Deadline& deadline) {
  const auto start = Clock::now();
  // The descriptor must be computed exactly as the model's training descriptors were (docs/design/classification.md).
  const PredictOptions predict{options.novelty_quantile};
  PipelineResult result = describe_mesh_bytes(bytes, options_for_recipe(model.recipe(), std::move(options)), deadline);
  const auto t = Clock::now();
  classify_described(result, model, predict);
  result.timings.classify = seconds_since(t);
  result.timings.total = seconds_since(start);
  return result;
}

}  // namespace wish
