// `wish map FILE --out sphere.ply [--method willmore|cmcf|linear|progressive] [--steps N] [--canonical none|isometric]
// [--json]` (methods: kMapMethodNames): the map of a closed genus-0 mesh onto the unit sphere that `wish describe`
// computes its descriptor on — by default the one default chain (core/pipeline/default_pipeline_options.hpp: the
// cMCF chain, then the canonical isometric relaxation); `--method willmore --canonical none` is the paper's conformal
// map (§4). Writes the sphere mesh (the prepared mesh's connectivity, unit-length vertices) and prints the quality
// report; a map that fails verification is not written and exits with kExitInvalid.
#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/command_registry.hpp"
#include "cli/enum_option.hpp"
#include "core/common/deadline.hpp"
#include "core/common/stage_profile.hpp"
#include "core/io/mesh_io.hpp"
#include "core/pipeline/default_pipeline_options.hpp"
#include "core/pipeline/describe_overrides.hpp"
#include "core/pipeline/pipeline.hpp"
#include "core/spherical_map/canonical_map.hpp"
#include "core/spherical_map/map_types.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "wire/wire_json.hpp"
#include "core/validation/mesh_report.hpp"

namespace wish::cli::map_command {  // one namespace per command: the commands compile in one unity batch
namespace {

struct MapArgs {
  std::string input;
  std::string output;
  DescribeOverrides overrides;  // --method, --steps (the step cap of that method's flow); no lmax here
  std::string solver = "cholmod";
  std::string canonical = to_string(default_pipeline_options().map.canonical.method);
  bool json = false;
  bool no_fallback = false;
  bool filtered = false;
  double timeout = 0;      // seconds; 0 = none
};

// The wire's map block (what the service sends, with the flow trace of every attempt) and the CLI's own fields.
nlohmann::json result_json(const SphericalMapResult& r, const PreparedMesh& prepared, const MapArgs& args) {
  nlohmann::json out = wire::map_block_json(r, /*quality=*/true, /*trace=*/true);
  nlohmann::json repairs = nlohmann::json::array();
  for (const RepairAction& a : prepared.repairs) repairs.push_back(wire::repair_json(a));
  out["input"] = args.input;
  out["output"] = r.ok() ? args.output : "";
  out["vertices"] = prepared.mesh.vertex_count();
  out["faces"] = prepared.mesh.face_count();
  out["repairs"] = repairs;
  out["failed_check"] = to_string(r.failed_check);
  out["chosen_attempt"] = r.chosen_attempt;
  return out;
}

void print_text(const SphericalMapResult& r, const PreparedMesh& prepared, const MapArgs& args) {
  std::cout << "input      " << args.input << " (" << prepared.mesh.vertex_count() << " vertices, "
            << prepared.mesh.face_count() << " faces)\n";
  for (const RepairAction& a : prepared.repairs) std::cout << "repair     " << a.message << "\n";
  for (const MapAttempt& a : r.attempts) {
    std::cout << "attempt    " << to_string(a.method) << (a.filtered ? " (filtered)" : "") << (a.needle ? " (needle retry)" : "") << ", " << a.steps.size()
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
  if (r.canonical.method != CanonicalMap::None)
    std::cout << "canonical  " << to_string(r.canonical.method) << ": " << to_string(r.canonical.stop) << " after "
              << r.canonical.iterations << " step(s), energy " << r.canonical.energy_start << " -> " << r.canonical.energy
              << ", " << r.canonical.seconds << " s\n";
  if (r.ok()) std::cout << "wrote      " << args.output << "\n";
}

CommandRunner setup_map(CLI::App& sub) {
  auto args = std::make_shared<MapArgs>();
  sub.add_option("file", args->input, "Input mesh (OBJ, PLY, OFF, STL): closed, genus 0")->required();
  sub.add_option("--out,-o", args->output, "Sphere mesh to write (format from the extension)")->required();
  const SphericalMapOptions defaults = default_pipeline_options().map;  // the one default, as `wish describe`'s
  add_enum_option(sub, "--method", args->overrides.method, kMapMethodNames, defaults.method, "Spherical map method");
  sub.add_option("--steps", args->overrides.max_flow_steps,
                 "Step cap of the chosen method's flow (default: willmore " + std::to_string(defaults.willmore.max_steps) +
                     ", cmcf " + std::to_string(defaults.cmcf.max_steps) +
                     "; not for linear, a single solve; the fallback chain keeps its own caps)")
      ->check(CLI::PositiveNumber);
  sub.add_option("--canonical", args->canonical,
                 "The map written: isometric (the canonical map the descriptor uses, relaxed from whichever map the "
                 "chain found, issue 37) | none (the chain's own conformal map, the paper's)")
      ->check(CLI::IsMember({"none", "isometric"}))->capture_default_str();
  sub.add_option("--solver", args->solver, "cholmod (default) or eigen")->check(CLI::IsMember({"cholmod", "eigen"}));
  sub.add_flag("--filtered", args->filtered, "Low-pass filtered Willmore flow (noisy segmentation meshes)");
  sub.add_flag("--no-fallback", args->no_fallback, "Do not try more steps / other flows / the linear map / the progressive embedding (the last resort) on failure");
  sub.add_option("--timeout", args->timeout, "Time limit in seconds (0: none)")->check(CLI::NonNegativeNumber);
  sub.add_flag("--json", args->json, "Print the report as JSON");
  return [args]() -> int {
    check_overrides(args->overrides, "--steps");
    const ReadResult read = [&] {
      const profile::ScopedStage stage("io.read");
      return read_mesh_file(args->input);
    }();
    // The pipeline's own first stages (map_mesh): the repairs, checks and chain `wish describe` runs, so that both
    // commands end on the same attempt for every mesh (issue 37).
    PipelineOptions options = default_pipeline_options();
    apply_overrides(args->overrides, options);
    options.map.solver = args->solver == "eigen" ? LinearSolverKind::EigenSimplicial : LinearSolverKind::Cholmod;
    options.map.fallback = !args->no_fallback;
    options.map.willmore.filtered = args->filtered;
    options.map.canonical.method = canonical_map_from_name(args->canonical);
    const Deadline deadline = args->timeout > 0 ? Deadline::after(std::chrono::duration<double>(args->timeout)) : Deadline{};
    const MappedMesh mapped = map_mesh(read.mesh, options, deadline);
    const PreparedMesh& prepared = mapped.prepared;
    const SphericalMapResult& result = mapped.map;
    if (result.ok()) {
      Mesh sphere;
      sphere.vertices = result.sphere;
      sphere.faces = prepared.mesh.faces;
      const profile::ScopedStage stage("io.write");
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

const bool registered = register_command({"map", "Map of a closed genus-0 mesh onto the unit sphere (the descriptor's map; --method willmore --canonical none: the paper's)",
                                          &setup_map, 20});

}  // namespace
}  // namespace wish::cli::map_command
