#include "wire/wire_json.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "core/common/errors.hpp"
#include "core/sh/sh_basis.hpp"
#include "core/sh/sh_invariants.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "wire/error_json.hpp"

namespace wish::wire {

namespace {

const char* const kAxes[3] = {"x", "y", "z"};

nlohmann::json vec3(const std::array<double, 3>& v) { return {json_number(v[0]), json_number(v[1]), json_number(v[2])}; }

nlohmann::json coefficient_column(const ShDescriptor& sh, int column) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index j = 0; j < sh.coefficients.rows(); ++j) {
    const auto c = sh.coefficients(j, column);
    out.push_back({json_number(c.real()), json_number(c.imag())});
  }
  return out;
}

[[noreturn]] void bad_descriptor(const std::string& what) {
  throw InvalidInputError("invalid_descriptor", "invalid SH descriptor JSON: " + what);
}

}  // namespace

nlohmann::json json_number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

double json_number_or_nan(const nlohmann::json& v) {
  return v.is_number() ? v.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

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
          {"zero_area_faces", r.zero_area_faces},
          {"duplicate_faces", r.duplicate_faces},
          {"unreferenced_vertices", r.unreferenced_vertices},
          {"duplicate_vertices", r.duplicate_vertices},
          {"orientation_consistent", r.orientation_consistent},
          {"misoriented_edges", r.misoriented_edges},
          {"signed_volume", json_number(r.signed_volume)},
          {"area", json_number(r.area)},
          {"bbox_min", vec3(r.bbox_min)},
          {"bbox_max", vec3(r.bbox_max)}};
}

nlohmann::json repair_json(const RepairAction& r) {
  return {{"code", r.code}, {"message", r.message}, {"count", r.count}};
}

nlohmann::json issue_json(const ValidationIssue& i) {
  return {{"code", i.code}, {"message", i.message}, {"details", details_json(i.details)}};
}

nlohmann::json mesh_block_json(const PreparedMesh& prepared, MeshFormat format, std::size_t bytes,
                               const std::vector<std::string>& read_notes, const std::string& filename) {
  nlohmann::json mesh{{"format", to_string(format)},
                      {"bytes", bytes},
                      {"read_notes", read_notes},
                      {"input", mesh_report_json(prepared.input_report)},
                      {"prepared", mesh_report_json(prepared.report)},
                      {"repairs", nlohmann::json::array()}};
  if (!filename.empty()) mesh["filename"] = filename;
  for (const auto& r : prepared.repairs) mesh["repairs"].push_back(repair_json(r));
  return mesh;
}

nlohmann::json map_quality_json(const MapQuality& q) {
  return {{"flipped_faces", q.flipped_faces},
          {"degenerate_faces", q.degenerate_faces},
          {"degree", q.degree},
          {"min_face_area", json_number(q.min_face_area)},
          {"conformal_mean", json_number(q.conformal_mean)},
          {"conformal_p99", json_number(q.conformal_p99)},
          {"conformal_max", json_number(q.conformal_max)},
          {"area_distortion", json_number(q.area_distortion)},
          {"roundness", json_number(q.roundness)},
          {"mobius_centroid", json_number(q.mobius_centroid)},
          {"mobius_iterations", q.mobius_iterations},
          {"min_face_height", json_number(q.min_face_height)},
          {"repaired_vertices", q.repaired_vertices},
          {"verdict", to_string(q.verdict)}};
}

nlohmann::json map_operator_json(const geometry::IntrinsicStats& s) {
  return {{"laplacian", geometry::to_string(s.kind)},
          {"mollify_epsilon", json_number(s.epsilon)},
          {"mollify_relative_epsilon", json_number(s.relative_epsilon)},
          {"zero_area_faces", s.zero_area_faces},
          {"mollified_faces", s.mollified_faces},
          {"negative_weights_before", s.negative_weights_before},
          {"negative_weights_after", s.negative_weights_after},
          {"flips", s.flips},
          {"flip_cap_hit", s.flip_cap_hit}};
}

nlohmann::json flow_step_json(const FlowStepRecord& s) {
  return {{"step", s.step},         {"tau", json_number(s.tau)},
          {"energy", json_number(s.energy)}, {"roundness", json_number(s.roundness)},
          {"eigen_residual", json_number(s.eigen_residual)}, {"accepted", s.accepted},
          {"seconds", json_number(s.seconds)}, {"note", s.note}};
}

nlohmann::json map_attempt_json(const MapAttempt& a, bool trace) {
  nlohmann::json out{{"method", to_string(a.method)}, {"filtered", a.filtered},
                     {"max_steps", a.max_steps},      {"status", to_string(a.status)},
                     {"steps", a.steps.size()},       {"seconds", json_number(a.seconds)},
                     {"cpu_seconds", json_number(a.cpu_seconds)},
                     {"repair_cpu_seconds", json_number(a.repair_cpu_seconds)},
                     {"repair_budget_stopped", a.repair_budget_stopped},
                     {"kernel_placed_vertices", a.kernel_placed_vertices},
                     {"everted", a.everted}};
  if (a.failed_check != MapCheck::None) out["failed_check"] = to_string(a.failed_check);
  out["stop"] = to_string(a.stop);
  if (!a.message.empty()) out["message"] = a.message;
  if (trace) {
    out["map_verified"] = a.map_verified;
    out["trace"] = nlohmann::json::array();
    for (const FlowStepRecord& s : a.steps) out["trace"].push_back(flow_step_json(s));
  }
  return out;
}

nlohmann::json area_distortion_json(const AreaDistortionFigures& f) {
  return {{"log_ratio_p99", json_number(f.log_ratio_p99)},
          {"log_ratio_max", json_number(f.log_ratio_max)},
          {"area_distortion", json_number(f.area_distortion)}};
}

nlohmann::json canonical_map_json(const CanonicalMapReport& r) {
  return {{"method", to_string(r.method)},
          {"stop", to_string(r.stop)},
          {"converged", r.converged},
          {"iterations", r.iterations},
          {"halvings", r.halvings},
          {"energy_start", json_number(r.energy_start)},
          {"energy", json_number(r.energy)},
          {"seconds", json_number(r.seconds)}};
}

nlohmann::json area_correction_json(const AreaCorrectionReport& r) {
  return {{"method", to_string(r.method)},
          {"stop", to_string(r.stop)},
          {"converged", r.converged},
          {"iterations", r.iterations},
          {"rejected_steps", r.rejected_steps},
          {"before", area_distortion_json(r.before)},
          {"after", area_distortion_json(r.after)},
          {"conformal_p99_before", json_number(r.conformal_p99_before)},
          {"conformal_p99_after", json_number(r.conformal_p99_after)},
          {"seconds", json_number(r.seconds)}};
}

nlohmann::json map_block_json(const SphericalMapResult& map, bool quality, bool trace) {
  nlohmann::json out{{"method", to_string(map.method_used)},
                     {"status", to_string(map.status)},
                     {"verdict", to_string(map.verdict)},
                     {"seconds", json_number(map.seconds)}};
  // Only when an area-aware correction was asked for (the default conformal map has none).
  if (map.area_correction.method != AreaCorrection::None) out["area_correction"] = area_correction_json(map.area_correction);
  // Only when the canonical map was asked for (issue 37): how the relaxation from the chain's map ended.
  if (map.canonical.method != CanonicalMap::None) out["canonical"] = canonical_map_json(map.canonical);
  if (quality) {
    out["operator"] = map_operator_json(map.operator_stats);
    out["quality"] = map_quality_json(map.quality);
    out["attempts"] = nlohmann::json::array();
    for (const auto& a : map.attempts) out["attempts"].push_back(map_attempt_json(a, trace));
    // Planned attempts the flow / chain budget stopped before they ran (issue 11: no budget stop is silent).
    out["skipped_for_budget"] = nlohmann::json::array();
    for (const auto& p : map.skipped_for_budget)
      out["skipped_for_budget"].push_back({{"method", to_string(p.method)}, {"max_steps", p.max_steps}});
  }
  return out;
}

nlohmann::json fit_options_json(const ShFitOptions& o) {
  return {{"lmax", o.lmax},
          {"regularization", o.regularization},
          {"weighting", to_string(o.weighting)},
          {"solver", to_string(o.solver)},
          {"band_size", o.band_size},
          {"gram", to_string(o.gram)}};
}

nlohmann::json fit_error_json(const FitError& e) {
  return {{"mean", json_number(e.mean)},
          {"rms", json_number(e.rms)},
          {"max", json_number(e.max)},
          {"mean_relative", json_number(e.mean_relative)},
          {"rms_relative", json_number(e.rms_relative)},
          {"max_relative", json_number(e.max_relative)}};
}

nlohmann::json descriptor_json(const ShDescriptor& d, const DescriptorJsonParts& parts) {
  nlohmann::json out{{"lmax", d.lmax}, {"options", fit_options_json(d.options)}, {"fit_error", fit_error_json(d.fit_error)}};
  if (parts.invariants) {
    nlohmann::json inv = nlohmann::json::array();
    for (Eigen::Index l = 0; l < d.invariants.size(); ++l) inv.push_back(json_number(d.invariants[l]));
    out["invariants"] = std::move(inv);
  }
  if (parts.coefficients) {
    out["index"] = "j = l^2 + l + m";
    nlohmann::json coefficients = nlohmann::json::object();
    for (int q = 0; q < 3; ++q) coefficients[kAxes[q]] = coefficient_column(d, q);
    out["coefficients"] = std::move(coefficients);
  }
  return out;
}

ShDescriptor descriptor_from_json(const nlohmann::json& json) {
  if (json.is_object() && json.contains("descriptor")) return descriptor_from_json(json["descriptor"]);
  if (!json.is_object()) bad_descriptor("expected an object");
  try {
    ShDescriptor d;
    if (!json.contains("lmax") || !json["lmax"].is_number_integer()) bad_descriptor("missing integer 'lmax'");
    d.lmax = json["lmax"].get<int>();
    if (d.lmax < 0 || d.lmax > kShMaxBasisLmax) bad_descriptor("'lmax' out of range");
    const Eigen::Index k = sh_count(d.lmax);
    if (json.contains("options")) {
      const auto& o = json["options"];
      d.options.lmax = o.value("lmax", d.lmax);
      d.options.regularization = o.value("regularization", d.options.regularization);
      d.options.weighting = fit_weighting_from_name(o.value("weighting", std::string("area")));
      d.options.solver = fit_solver_from_name(o.value("solver", std::string("direct")));
      d.options.band_size = o.value("band_size", d.options.band_size);
      d.options.gram = gram_method_from_name(o.value("gram", std::string("quadrature")));
    } else {
      d.options.lmax = d.lmax;
    }
    if (!json.contains("coefficients") || !json["coefficients"].is_object())
      bad_descriptor("missing object 'coefficients'");
    d.coefficients.resize(k, 3);
    for (int q = 0; q < 3; ++q) {
      const auto& col = json["coefficients"].value(kAxes[q], nlohmann::json());
      if (!col.is_array() || Eigen::Index(col.size()) != k)
        bad_descriptor(std::string("'coefficients.") + kAxes[q] + "' must hold (lmax+1)^2 = " + std::to_string(k) +
                       " pairs");
      for (Eigen::Index j = 0; j < k; ++j) {
        const auto& pair = col[size_t(j)];
        if (!pair.is_array() || pair.size() != 2 || !pair[0].is_number() || !pair[1].is_number())
          bad_descriptor(std::string("'coefficients.") + kAxes[q] + "[" + std::to_string(j) + "]' is not [re, im]");
        d.coefficients(j, q) = {pair[0].get<double>(), pair[1].get<double>()};
      }
    }
    d.invariants = sh_invariants(d.coefficients);  // recomputed: always consistent with the coefficients
    if (json.contains("fit_error")) {
      const auto& e = json["fit_error"];
      d.fit_error.mean = e.value("mean", 0.0);
      d.fit_error.rms = e.value("rms", 0.0);
      d.fit_error.max = e.value("max", 0.0);
      d.fit_error.mean_relative = e.value("mean_relative", 0.0);
      d.fit_error.rms_relative = e.value("rms_relative", 0.0);
      d.fit_error.max_relative = e.value("max_relative", 0.0);
    }
    return d;
  } catch (const nlohmann::json::exception& e) {
    bad_descriptor(e.what());
  }
}

nlohmann::json novelty_explanation_json(const NoveltyAssessment& n, const std::vector<std::string>& labels) {
  nlohmann::json out = nlohmann::json::object();
  if (n.class_ratios.size() != labels.size() || labels.size() < 2) return out;
  std::vector<std::size_t> order(labels.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return n.class_ratios[a] < n.class_ratios[b]; });
  nlohmann::json classes = nlohmann::json::array();
  for (std::size_t i : order) classes.push_back({{"label", labels[i]}, {"ratio", json_number(n.class_ratios[i])}});
  const auto g = static_cast<std::size_t>(n.group);
  out["nearest_class"] = g < labels.size() ? labels[g] : labels[order.front()];
  out["distance_ratio"] = json_number(g < labels.size() ? n.class_ratios[g] : n.class_ratios[order.front()]);
  out["classes"] = std::move(classes);
  return out;
}

nlohmann::json prediction_json(const Prediction& p, const std::string& model_name, const std::string& model_version,
                               const std::optional<RecipeConformance>& recipe) {
  nlohmann::json probs = nlohmann::json::array();
  for (const auto& [label, prob] : p.probabilities) probs.push_back({{"label", label}, {"probability", json_number(prob)}});
  nlohmann::json out{{"label", p.label},
                     {"probabilities", std::move(probs)},
                     {"margin", json_number(p.margin)},
                     {"model", {{"name", model_name}, {"version", model_version}}}};
  out["novel"] = nullptr;
  if (p.novelty) {
    out["novel"] = p.novelty->novel;
    out["novelty"] = {{"computed", true},
                      {"score", json_number(p.novelty->score)},
                      {"p_value", json_number(p.novelty->p_value)},
                      {"threshold", json_number(p.novelty->threshold)},
                      {"quantile", json_number(p.novelty->quantile)}};
    std::vector<std::string> labels;
    for (const auto& [label, prob] : p.probabilities) labels.push_back(label);
    out["novelty"].update(novelty_explanation_json(*p.novelty, labels));
  } else {
    out["novelty"] = {{"computed", false},
                      {"reason", "the model has no novelty calibration (a model file written before format 3)"}};
  }
  if (recipe) {
    out["recipe_match"] = recipe->match;
    out["method_used"] = to_string(recipe->method_used);
    out["recipe_method"] = to_string(recipe->recipe_method);
    if (recipe->canonical != CanonicalMap::None) {
      // The path-dependence that remains (issue 37): a relaxation stopped by its budget is still the recipe's map.
      out["canonical_converged"] = recipe->canonical_converged;
      out["canonical_excess"] = json_number(recipe->canonical_excess);
    }
  }
  return out;
}

nlohmann::json mesh_geometry_json(const Mesh& m) {
  nlohmann::json vertices = nlohmann::json::array(), faces = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
    vertices.push_back({json_number(m.vertices(i, 0)), json_number(m.vertices(i, 1)), json_number(m.vertices(i, 2))});
  for (Eigen::Index i = 0; i < m.faces.rows(); ++i) faces.push_back({m.faces(i, 0), m.faces(i, 1), m.faces(i, 2)});
  return {{"vertices", std::move(vertices)}, {"faces", std::move(faces)}};
}

nlohmann::json geometry_json(const Mesh& mesh, const Eigen::MatrixX3d& sphere, const GeometryJsonParts& parts) {
  auto flat_rows = [](const auto& matrix) {
    nlohmann::json out = nlohmann::json::array();
    out.get_ref<nlohmann::json::array_t&>().reserve(static_cast<std::size_t>(matrix.size()));
    for (Eigen::Index i = 0; i < matrix.rows(); ++i)
      for (Eigen::Index c = 0; c < matrix.cols(); ++c) {
        if constexpr (std::is_integral_v<typename std::decay_t<decltype(matrix)>::Scalar>) out.push_back(matrix(i, c));
        else out.push_back(json_number(matrix(i, c)));
      }
    return out;
  };
  auto flat_vector = [](const Eigen::VectorXd& v) {
    nlohmann::json out = nlohmann::json::array();
    for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(json_number(v[i]));
    return out;
  };
  nlohmann::json out{{"vertex_count", mesh.vertices.rows()}, {"face_count", mesh.faces.rows()}};
  if (parts.mesh) {
    out["vertices"] = flat_rows(mesh.vertices);
    out["faces"] = flat_rows(mesh.faces);
  }
  if (parts.sphere) out["sphere"] = flat_rows(sphere);
  if (parts.distortion) {
    const auto d = spherical::face_distortion(mesh.vertices, mesh.faces, sphere);
    out["conformal_distortion"] = flat_vector(d.conformal);
    out["area_ratio"] = flat_vector(d.area_ratio);
  }
  return out;
}

nlohmann::json timings_json(const StageTimings& t, bool classify) {
  nlohmann::json out{{"read", t.read}, {"validate", t.validate}, {"map", t.map}, {"fit", t.fit}, {"total", t.total}};
  if (classify) out["classify"] = t.classify;
  return out;
}

}  // namespace wish::wire
