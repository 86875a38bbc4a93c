#pragma once
// The one JSON wire encoding of the core structs (the schemas of proto/openapi.json), used by the service
// (result_json.cpp assembles the DescribeResult) and by the CLI (`wish inspect --json`, `wish describe --json`,
// `wish reconstruct`), so the CLI prints the same shapes the service sends and users can switch between them.
// Errors and their details are encoded in error_mapping.hpp. Core headers stay JSON-free: the encoding lives here.
// Includes Eigen through the core headers: never include from an http_*.cpp file.
//
// Numbers: JSON has no NaN / Inf, so a non-finite figure (e.g. an undefined conformal ratio) is encoded as null.
//
// Descriptor layout (DescriptorBlock; the service adds "settings"):
// {
//   "lmax": L,
//   "options": {"lmax", "regularization", "weighting": "area"|"uniform", "solver": "direct"|"banded", "band_size",
//               "gram": "quadrature"|"product"},
//   "fit_error": {"mean", "rms", "max", "mean_relative", "rms_relative", "max_relative"},
//   "invariants": [xi_0, ..., xi_L],                                  // sum over x, y, z          (optional part)
//   "index": "j = l^2 + l + m",                                       // with the coefficients
//   "coefficients": {"x": [[re, im], ...], "y": [...], "z": [...]}    // (L+1)^2 pairs each, rows j (optional part)
// }

#include <string>

#include <nlohmann/json.hpp>

#include "core/pipeline/pipeline.hpp"

namespace wish::server {

nlohmann::json json_number(double value);          // null when not finite
double json_number_or_nan(const nlohmann::json& value);  // the inverse for printing: NaN for null

nlohmann::json mesh_report_json(const MeshReport& report);          // MeshReport
nlohmann::json repair_json(const RepairAction& repair);             // Repair: {"code", "message", "count"}
nlohmann::json issue_json(const ValidationIssue& issue);            // {"code", "message", "details"}

nlohmann::json map_quality_json(const MapQuality& quality);         // MapQuality
nlohmann::json map_attempt_json(const MapAttempt& attempt);         // MapAttempt
nlohmann::json map_operator_json(const geometry::IntrinsicStats& stats);  // the operator of a map: mollification, flips
// MapBlock: {"method", "status", "seconds"} and, with `quality`, "quality" and "attempts".
nlohmann::json map_block_json(const SphericalMapResult& map, bool quality);

struct DescriptorJsonParts {
  bool invariants = true, coefficients = true;
};
nlohmann::json fit_options_json(const ShFitOptions& options);
nlohmann::json fit_error_json(const FitError& error);
nlohmann::json descriptor_json(const ShDescriptor& descriptor, const DescriptorJsonParts& parts = {});
// Accepts the layout above, also wrapped as {"descriptor": {...}, ...}: a `wish describe --json` entry or a
// /v1/describe response with include=coefficients ("options" absent: defaults with options.lmax = lmax).
// Invariants are recomputed from the coefficients. Throws InvalidInputError ("invalid_descriptor") naming the field.
ShDescriptor descriptor_from_json(const nlohmann::json& json);

// Prediction: {"label", "probabilities": [{"label", "probability"}], "margin", "model": {"name", "version"}}.
nlohmann::json prediction_json(const Prediction& prediction, const std::string& model_name,
                               const std::string& model_version);
nlohmann::json mesh_geometry_json(const Mesh& mesh);  // {"vertices": [[x, y, z], ...], "faces": [[i, j, k], ...]}
// Timings: read, validate, map, fit, total; "classify" too with `classify`.
nlohmann::json timings_json(const StageTimings& timings, bool classify = false);

}  // namespace wish::server
