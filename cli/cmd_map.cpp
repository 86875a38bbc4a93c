// `wish map FILE --out sphere.ply [--method willmore|cmcf|linear] [--steps N] [--json]`: conformal map of a closed
// genus-0 mesh onto the unit sphere (paper §4). Writes the sphere mesh (the prepared mesh's connectivity, unit-length
// vertices) and prints the quality report; a map that fails verification is not written and exits with kExitInvalid.
#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/command_registry.hpp"
#include "core/common/deadline.hpp"
#include "core/io/mesh_io.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "server/wire_json.hpp"
#include "core/validation/mesh_report.hpp"

namespace wish::cli {
namespace {

struct MapArgs {
  std::string input;
  std::string output;
  std::string method = "willmore";
  std::string solver = "cholmod";
  int steps = 0;           // 0: the method's default cap
  bool json = false;
  bool no_fallback = false;
  bool filtered = false;
  double timeout = 0;      // seconds; 0 = none
};

nlohmann::json quality_json(const MapQuality& q) {
  return {{"flipped_faces", q.flipped_faces},     {"degenerate_faces", q.degenerate_faces},
          {"degree", q.degree},                   {"min_face_area", q.min_face_area},
          {"conformal_mean", q.conformal_mean},   {"conformal_p99", q.conformal_p99},
          {"conformal_max", q.conformal_max},     {"area_distortion", q.area_distortion},
          {"roundness", q.roundness},             {"mobius_centroid", q.mobius_centroid},
          {"mobius_iterations", q.mobius_iterations}, {"min_face_height", q.min_face_height},
          {"repaired_vertices", q.repaired_vertices}};
}

nlohmann::json result_json(const SphericalMapResult& r, const PreparedMesh& prepared, const MapArgs& args) {
  nlohmann::json attempts = nlohmann::json::array();
  for (const MapAttempt& a : r.attempts) {
    nlohmann::json steps = nlohmann::json::array();
    for (const FlowStepRecord& s : a.steps)
      steps.push_back({{"step", s.step}, {"tau", s.tau}, {"energy", s.energy}, {"roundness", s.roundness},
                       {"eigen_residual", s.eigen_residual}, {"accepted", s.accepted}, {"seconds", s.seconds},
                       {"note", s.note}});
    attempts.push_back({{"method", to_string(a.method)}, {"filtered", a.filtered}, {"max_steps", a.max_steps},
                        {"status", to_string(a.status)}, {"failed_check", to_string(a.failed_check)}, {"stop", to_string(a.stop)}, {"message", a.message},
                        {"quality", quality_json(a.quality)}, {"steps", steps}, {"seconds", a.seconds},
                        {"map_verified", a.map_verified}});
  }
  nlohmann::json repairs = nlohmann::json::array();
  for (const RepairAction& a : prepared.repairs) repairs.push_back({{"code", a.code}, {"message", a.message}});
  return {{"input", args.input},
          {"output", r.ok() ? args.output : ""},
          {"vertices", prepared.mesh.vertex_count()},
          {"faces", prepared.mesh.face_count()},
          {"repairs", repairs},
          {"status", to_string(r.status)},
          {"failed_check", to_string(r.failed_check)},
          {"verdict", to_string(r.verdict)},
          {"operator", server::map_operator_json(r.operator_stats)},
          {"method", to_string(r.method_used)},
          {"quality", quality_json(r.quality)},
          {"attempts", attempts},
          {"chosen_attempt", r.chosen_attempt},
          {"seconds", r.seconds}};
}

void print_text(const SphericalMapResult& r, const PreparedMesh& prepared, const MapArgs& args) {
  std::cout << "input      " << args.input << " (" << prepared.mesh.vertex_count() << " vertices, "
            << prepared.mesh.face_count() << " faces)\n";
  for (const RepairAction& a : prepared.repairs) std::cout << "repair     " << a.message << "\n";
  for (const MapAttempt& a : r.attempts) {
    std::cout << "attempt    " << to_string(a.method) << (a.filtered ? " (filtered)" : "") << ", " << a.steps.size()
              << " step(s), " << to_string(a.status) << (a.failed_check == MapCheck::None ? "" : std::string(" [") + to_string(a.failed_check) + "]")
              << ", " << a.seconds << " s\n";
    if (!a.message.empty()) std::cout << "           " << a.message << "\n";
  }
  const MapQuality& q = r.quality;
  std::cout << "status     " << to_string(r.status) << (r.failed_check == MapCheck::None ? "" : std::string(" [") + to_string(r.failed_check) + "]") << "\n"
            << "verdict    " << to_string(r.verdict) << "\n"
            << "operator   " << geometry::to_string(r.operator_stats.kind) << ": epsilon " << r.operator_stats.epsilon
            << " (" << r.operator_stats.zero_area_faces << " zero-area faces), " << r.operator_stats.negative_weights_before
            << " negative weights before, " << r.operator_stats.flips << " flips\n"
            << "method     " << to_string(r.method_used) << "\n"
            << "flips      " << q.flipped_faces << "  degenerate " << q.degenerate_faces << "  degree " << q.degree
            << "  repaired vertices " << q.repaired_vertices << "\n"
            << "conformal  K mean " << q.conformal_mean << "  p99 " << q.conformal_p99 << "  max " << q.conformal_max << "\n"
            << "area       distortion " << q.area_distortion << "\n"
            << "roundness  " << q.roundness << "  (before projection)\n"
            << "mobius     centroid " << q.mobius_centroid << " after " << q.mobius_iterations << " iteration(s)\n"
            << "time       " << r.seconds << " s\n";
  if (r.ok()) std::cout << "wrote      " << args.output << "\n";
}

CommandRunner setup_map(CLI::App& sub) {
  auto args = std::make_shared<MapArgs>();
  sub.add_option("file", args->input, "Input mesh (OBJ, PLY, OFF, STL): closed, genus 0")->required();
  sub.add_option("--out,-o", args->output, "Sphere mesh to write (format from the extension)")->required();
  sub.add_option("--method", args->method, "willmore (default), cmcf or linear")
      ->check(CLI::IsMember({"willmore", "cmcf", "linear"}));
  sub.add_option("--steps", args->steps, "Flow step cap (default: 20 for willmore, 30 for cmcf)")->check(CLI::PositiveNumber);
  sub.add_option("--solver", args->solver, "cholmod (default) or eigen")->check(CLI::IsMember({"cholmod", "eigen"}));
  sub.add_flag("--filtered", args->filtered, "Low-pass filtered Willmore flow (noisy segmentation meshes)");
  sub.add_flag("--no-fallback", args->no_fallback, "Do not try more steps / filtered flow / cMCF / linear method on failure");
  sub.add_option("--timeout", args->timeout, "Time limit in seconds (0: none)")->check(CLI::NonNegativeNumber);
  sub.add_flag("--json", args->json, "Print the report as JSON");
  return [args]() -> int {
    const ReadResult read = read_mesh_file(args->input);
    const PreparedMesh prepared = prepare_for_mapping(read.mesh);
    require_mappable(prepared);
    SphericalMapOptions options;
    options.method = map_method_from_name(args->method);
    options.solver = args->solver == "eigen" ? LinearSolverKind::EigenSimplicial : LinearSolverKind::Cholmod;
    options.fallback = !args->no_fallback;
    options.willmore.filtered = args->filtered;
    if (args->steps > 0) options.willmore.max_steps = options.cmcf.max_steps = args->steps;
    const Deadline deadline = args->timeout > 0 ? Deadline::after(std::chrono::duration<double>(args->timeout)) : Deadline{};
    const SphericalMapResult result = compute_spherical_map(prepared.mesh, options, deadline);
    if (result.ok()) {
      Mesh sphere;
      sphere.vertices = result.sphere;
      sphere.faces = prepared.mesh.faces;
      write_mesh_file(sphere, args->output);
    }
    if (args->json)
      std::cout << result_json(result, prepared, *args).dump(2) << "\n";
    else
      print_text(result, prepared, *args);
    if (!result.ok()) {
      std::cerr << "wish map: the map failed verification (" << to_string(result.status) << ", "
                << to_string(result.failed_check) << "); nothing written\n";
      return kExitInvalid;
    }
    return kExitOk;
  };
}

const bool registered = register_command({"map", "Conformal map of a closed genus-0 mesh onto the unit sphere (Willmore flow)",
                                          &setup_map, 20});

}  // namespace
}  // namespace wish::cli
