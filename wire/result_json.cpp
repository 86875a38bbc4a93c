#include "wire/result_json.hpp"

#include "wire/wire_json.hpp"

namespace wish::wire {

nlohmann::json result_json(const PipelineResult& result, const ResultJsonOptions& options) {
  nlohmann::json out;

  out["mesh"] = mesh_block_json(result.prepared, result.format, options.bytes, result.read_notes, options.filename);

  out["map"] = map_block_json(result.map, options.quality);

  out["descriptor"] = descriptor_json(result.sh, {.invariants = options.invariants, .coefficients = options.coefficients});
  out["descriptor"]["settings"] = options.settings;

  if (result.prediction)
    out["prediction"] = prediction_json(*result.prediction, options.model_name, options.model_version, result.recipe);

  if (options.reconstruction && result.reconstruction) {
    out["reconstruction"] = mesh_geometry_json(*result.reconstruction);
    out["reconstruction"]["level"] = options.reconstruction_level;
  }

  if (options.mesh || options.sphere || options.distortion)
    out["geometry"] = geometry_json(result.prepared.mesh, result.map.sphere,
                                    {.mesh = options.mesh, .sphere = options.sphere, .distortion = options.distortion});

  out["timings"] = timings_json(result.timings, result.prediction.has_value());
  return out;
}

}  // namespace wish::wire
