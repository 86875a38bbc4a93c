#include "server/result_json.hpp"

#include "server/wire_json.hpp"

namespace wish::server {

nlohmann::json result_json(const PipelineResult& result, const ResultJsonOptions& options) {
  nlohmann::json out;

  nlohmann::json mesh{{"format", to_string(result.format)},
                      {"bytes", options.bytes},
                      {"read_notes", result.read_notes},
                      {"input", mesh_report_json(result.prepared.input_report)},
                      {"prepared", mesh_report_json(result.prepared.report)},
                      {"repairs", nlohmann::json::array()}};
  if (!options.filename.empty()) mesh["filename"] = options.filename;
  for (const auto& r : result.prepared.repairs) mesh["repairs"].push_back(repair_json(r));
  out["mesh"] = std::move(mesh);

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

}  // namespace wish::server
