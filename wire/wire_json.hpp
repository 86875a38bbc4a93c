#pragma once
// The one JSON wire encoding of the core structs (the schemas of proto/openapi.json), used by the service
// (result_json.cpp assembles the DescribeResult) and by the CLI (`wish inspect --json`, `wish describe --json`,
// `wish map --json`, `wish predict --json`, `wish reconstruct`), so the CLI prints the same shapes the service sends and users can switch between them.
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

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/pipeline/pipeline.hpp"

namespace wish::wire {

nlohmann::json json_number(double value);          // null when not finite
double json_number_or_nan(const nlohmann::json& value);  // the inverse for printing: NaN for null

nlohmann::json mesh_report_json(const MeshReport& report);          // MeshReport
nlohmann::json repair_json(const RepairAction& repair);             // Repair: {"code", "message", "count"}
nlohmann::json issue_json(const ValidationIssue& issue);            // {"code", "message", "details"}
// MeshBlock: {"format", "bytes", "read_notes", "input": MeshReport (as read), "prepared": MeshReport (after repairs),
// "repairs": [Repair]} and "filename" when not empty. The service's results and `wish inspect --json` both use it.
nlohmann::json mesh_block_json(const PreparedMesh& prepared, MeshFormat format, std::size_t bytes,
                               const std::vector<std::string>& read_notes, const std::string& filename = "");

nlohmann::json map_quality_json(const MapQuality& quality);         // MapQuality
// FlowStepRecord: {"step", "tau", "energy", "roundness", "eigen_residual", "accepted", "seconds", "note"}.
nlohmann::json flow_step_json(const FlowStepRecord& step);
// MapAttempt; with `trace` also "map_verified" and "trace": the flow's step records (`wish map --json`).
nlohmann::json map_attempt_json(const MapAttempt& attempt, bool trace = false);
nlohmann::json map_operator_json(const geometry::IntrinsicStats& stats);  // the operator of a map: mollification, flips
// MapBlock: {"method", "status", "verdict", "seconds"} and, with `quality`, "operator", "quality" and "attempts"
// (with `trace`, each attempt's step records).
nlohmann::json map_block_json(const SphericalMapResult& map, bool quality, bool trace = false);

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

// Prediction: {"label", "probabilities": [{"label", "probability"}], "margin", "model": {"name", "version"}},
// plus, when the recipe check ran: "recipe_match" (false: the map came from another method than the model's,
// accepted by its off_recipe policy), "method_used", "recipe_method"; always "novel" (true: none of the known
// types, by the model's novelty threshold; null: not computed) and "novelty" ({"computed": true, "score",
// "p_value", "threshold", "quantile", and novelty_explanation_json's keys} or {"computed": false, "reason"}).
// Why a sample is (not) novel (issue 38 item 3), merged into a "novelty" object: "nearest_class" (the class it is
// most like, relative to that class's spread), "distance_ratio" (its score over that class's threshold: the
// distance in units of the class's calibration spread; novel above 1) and "classes": [{"label", "ratio"}] for every
// class, nearest first. Empty (nothing to merge) for a one-set figure (model format 3), which has no classes.
// `labels`: the model's classes in its order.
nlohmann::json novelty_explanation_json(const NoveltyAssessment& novelty, const std::vector<std::string>& labels);
nlohmann::json prediction_json(const Prediction& prediction, const std::string& model_name,
                               const std::string& model_version,
                               const std::optional<RecipeConformance>& recipe = std::nullopt);
nlohmann::json mesh_geometry_json(const Mesh& mesh);  // {"vertices": [[x, y, z], ...], "faces": [[i, j, k], ...]}
// GeometryBlock, for viewers: flat arrays of the mesh that was mapped (after repairs; the order of its vertices
// and faces is that of `prepared` in the mesh block), its sphere map and the per-face distortion of the map.
//   "vertex_count": V, "face_count": F,
//   "vertices": [x0, y0, z0, x1, ...] (3V),  "faces": [a0, b0, c0, ...] (3F, 0-based, outward orientation)  (mesh)
//   "sphere": [u0x, u0y, u0z, ...] (3V, unit vectors: the image of each vertex)                          (sphere)
//   "conformal_distortion": [K_0, ...] (F; K = sigma1/sigma2 >= 1, null when a sphere triangle is degenerate),
//   "area_ratio": [r_0, ...] (F; sphere area share / input area share, 1 = equiareal)                 (distortion)
// The map block's conformal mean / p99 / max and area_distortion are summaries of these two arrays.
struct GeometryJsonParts {
  bool mesh = false, sphere = false, distortion = false;
};
nlohmann::json geometry_json(const Mesh& mesh, const Eigen::MatrixX3d& sphere, const GeometryJsonParts& parts);
// Timings: read, validate, map, fit, total; "classify" too with `classify`.
nlohmann::json timings_json(const StageTimings& timings, bool classify = false);

}  // namespace wish::wire
