#include "server/result_json.hpp"

#include <cmath>

namespace wish::server {

namespace {

// JSON has no NaN / Inf: a non-finite figure (e.g. an undefined conformal ratio) is sent as null.
nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json vec3(const std::array<double, 3>& v) { return {num(v[0]), num(v[1]), num(v[2])}; }

nlohmann::json quality_json(const MapQuality& q) {
  return {{"flipped_faces", q.flipped_faces},     {"degenerate_faces", q.degenerate_faces},
          {"degree", q.degree},                   {"min_face_area", num(q.min_face_area)},
          {"conformal_mean", num(q.conformal_mean)}, {"conformal_p99", num(q.conformal_p99)},
          {"conformal_max", num(q.conformal_max)}, {"area_distortion", num(q.area_distortion)},
          {"roundness", num(q.roundness)},         {"mobius_centroid", num(q.mobius_centroid)}};
}

nlohmann::json coefficient_column(const ShDescriptor& sh, int column) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index j = 0; j < sh.coefficients.rows(); ++j) {
    const auto c = sh.coefficients(j, column);
    out.push_back({num(c.real()), num(c.imag())});
  }
  return out;
}

}  // namespace

nlohmann::json mesh_report_json(const MeshReport& r) {
  return {{"vertices", r.vertices},
          {"edges", r.edges},
          {"faces", r.faces},
          {"components", r.components},
          {"boundary_edges", r.boundary_edges},
          {"nonmanifold_edges", r.nonmanifold_edges},
          {"nonmanifold_vertices", r.nonmanifold_vertices},
          {"euler_characteristic", r.euler_characteristic},
          {"genus", r.genus ? nlohmann::json(*r.genus) : nlohmann::json(nullptr)},
          {"degenerate_faces", r.degenerate_faces},
          {"duplicate_faces", r.duplicate_faces},
          {"unreferenced_vertices", r.unreferenced_vertices},
          {"duplicate_vertices", r.duplicate_vertices},
          {"orientation_consistent", r.orientation_consistent},
          {"signed_volume", num(r.signed_volume)},
          {"area", num(r.area)},
          {"bbox_min", vec3(r.bbox_min)},
          {"bbox_max", vec3(r.bbox_max)}};
}

nlohmann::json result_json(const PipelineResult& result, const ResultJsonOptions& options) {
  nlohmann::json out;

  nlohmann::json mesh{{"format", to_string(result.format)},
                      {"bytes", options.bytes},
                      {"read_notes", result.read_notes},
                      {"input", mesh_report_json(result.prepared.input_report)},
                      {"prepared", mesh_report_json(result.prepared.report)},
                      {"repairs", nlohmann::json::array()}};
  if (!options.filename.empty()) mesh["filename"] = options.filename;
  for (const auto& r : result.prepared.repairs)
    mesh["repairs"].push_back({{"code", r.code}, {"message", r.message}, {"count", r.count}});
  out["mesh"] = std::move(mesh);

  nlohmann::json map{{"method", to_string(result.map.method_used)},
                     {"status", to_string(result.map.status)},
                     {"seconds", num(result.map.seconds)}};
  if (options.quality) {
    map["quality"] = quality_json(result.map.quality);
    map["attempts"] = nlohmann::json::array();
    for (const auto& a : result.map.attempts) {
      nlohmann::json attempt{{"method", to_string(a.method)}, {"filtered", a.filtered},
                             {"max_steps", a.max_steps},      {"status", to_string(a.status)},
                             {"steps", a.steps.size()},       {"seconds", num(a.seconds)}};
      if (!a.failed_check.empty()) attempt["failed_check"] = a.failed_check;
      if (!a.message.empty()) attempt["message"] = a.message;
      map["attempts"].push_back(std::move(attempt));
    }
  }
  out["map"] = std::move(map);

  const auto& sh = result.sh;
  nlohmann::json descriptor{{"lmax", sh.lmax},
                            {"settings", options.settings},
                            {"fit_error",
                             {{"mean", num(sh.fit_error.mean)},
                              {"rms", num(sh.fit_error.rms)},
                              {"max", num(sh.fit_error.max)},
                              {"mean_relative", num(sh.fit_error.mean_relative)},
                              {"rms_relative", num(sh.fit_error.rms_relative)},
                              {"max_relative", num(sh.fit_error.max_relative)}}}};
  if (options.invariants) {
    nlohmann::json inv = nlohmann::json::array();
    for (Eigen::Index l = 0; l < sh.invariants.size(); ++l) inv.push_back(num(sh.invariants[l]));
    descriptor["invariants"] = std::move(inv);
  }
  if (options.coefficients)
    descriptor["coefficients"] = {{"x", coefficient_column(sh, 0)},
                                  {"y", coefficient_column(sh, 1)},
                                  {"z", coefficient_column(sh, 2)}};
  out["descriptor"] = std::move(descriptor);

  if (result.prediction) {
    const auto& p = *result.prediction;
    nlohmann::json probs = nlohmann::json::array();
    for (const auto& [label, prob] : p.probabilities) probs.push_back({{"label", label}, {"probability", num(prob)}});
    out["prediction"] = {{"label", p.label},
                         {"probabilities", std::move(probs)},
                         {"margin", num(p.margin)},
                         {"model", {{"name", options.model_name}, {"version", options.model_version}}}};
  }

  if (options.reconstruction && result.reconstruction) {
    const Mesh& m = *result.reconstruction;
    nlohmann::json vertices = nlohmann::json::array(), faces = nlohmann::json::array();
    for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
      vertices.push_back({num(m.vertices(i, 0)), num(m.vertices(i, 1)), num(m.vertices(i, 2))});
    for (Eigen::Index i = 0; i < m.faces.rows(); ++i) faces.push_back({m.faces(i, 0), m.faces(i, 1), m.faces(i, 2)});
    out["reconstruction"] = {{"level", options.reconstruction_level}, {"vertices", std::move(vertices)}, {"faces", std::move(faces)}};
  }

  const auto& t = result.timings;
  out["timings"] = {{"read", t.read}, {"validate", t.validate}, {"map", t.map}, {"fit", t.fit}, {"total", t.total}};
  if (result.prediction) out["timings"]["classify"] = t.classify;
  return out;
}

}  // namespace wish::server
