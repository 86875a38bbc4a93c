#pragma once
// PipelineResult -> the DescribeResult JSON of proto/openapi.json (mesh, map, descriptor, prediction,
// reconstruction, timings), assembled from the per-struct encoders of wire_json.hpp (shared with the CLI).
// Includes Eigen through pipeline.hpp: never include from an http_*.cpp file.

#include <string>

#include <nlohmann/json.hpp>

#include "core/pipeline/pipeline.hpp"

namespace wish::wire {

struct ResultJsonOptions {
  bool coefficients = false, invariants = true, quality = true, reconstruction = false;
  int reconstruction_level = 3;
  bool mesh = false, sphere = false, distortion = false;  // parts of the "geometry" block (wire_json.hpp)
  std::string filename;                     // "" when the mesh came as a raw body
  std::size_t bytes = 0;                    // size of the uploaded mesh
  nlohmann::json settings;                  // DescriptorSettingsUsed: source, lmax, method, steps, ...
  std::string model_name, model_version;    // for the prediction block
};

nlohmann::json result_json(const PipelineResult& result, const ResultJsonOptions& options);

}  // namespace wish::wire
