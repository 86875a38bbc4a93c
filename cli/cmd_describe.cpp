// `wish describe FILE... --lmax L [--json|--csv] [--method willmore|cmcf|linear] [--steps N] [--weights area|uniform]`:
// mesh -> validate/repair -> spherical map -> SH fit -> invariants, with the timings of every stage.
//   default: a short table per file;  --json: an array, one object per file, its "descriptor", "map" and "timings"
//   blocks in the service's layout (wire/wire_json.hpp: the same encoders as /v1/describe);  --csv: one row per mesh: file, n_vertices, n_faces, map method/status, fit errors,
//   timings, xi_0..xi_L (what a notebook wants).
// A label volume (NIfTI-1, TIFF; by content; the volume options of `wish mesh-labels`) gives one result per kept
// object, keyed by label id ("label_id"; JSON also an "object" block; CSV column label_id, empty for meshes).
// A file or object that fails is reported (JSON: "error"; CSV/table: on stderr) and the others still run; exit status 1 then.
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/command_registry.hpp"
#include "cli/enum_option.hpp"
#include "cli/file_bytes.hpp"
#include "cli/volume_options.hpp"
#include "cli/volume_rows.hpp"
#include "core/classify/default_recipe.hpp"
#include "core/pipeline/default_pipeline_options.hpp"
#include "core/common/errors.hpp"
#include "core/pipeline/describe_overrides.hpp"
#include "core/pipeline/pipeline.hpp"
#include "core/sh/sh_fit_names.hpp"
#include "core/sh/sh_lmax_range.hpp"
#include "core/spherical_map/map_types.hpp"
#include "wire/error_json.hpp"
#include "wire/wire_json.hpp"

namespace wish::cli::describe_command {  // one namespace per command: the commands compile in one unity batch
namespace {

using wire::json_number_or_nan;

// The defaults are core's one default (default_pipeline_options(): the training recipe's map and fit, issue 37).
const PipelineOptions kDefaults = default_pipeline_options();

struct DescribeOptions {
  std::vector<std::string> files;
  DescribeOverrides overrides;  // --method, --lmax, --steps
  bool json = false, csv = false;
  FitWeighting weights = kDefaults.sh.weighting;
  FitSolver solver = kDefaults.sh.solver;
  std::string area_correction = to_string(kDefaults.map.area_correction.method);
  std::string canonical = to_string(kDefaults.map.canonical.method);
  std::string sampling = to_string(kDefaults.sh.sampling);
  double regularization = kDefaults.sh.regularization;
  bool quiet = false;
  VolumeCliOptions volume;
};

// The result blocks of one described mesh (a file's, or a volume object's surface).
void describe_into(nlohmann::json& out, const PipelineResult& r) {
  out["n_vertices"] = r.prepared.mesh.vertex_count();
  out["n_faces"] = r.prepared.mesh.face_count();
  out["map"] = wire::map_block_json(r.map, /*quality=*/true);
  // Kept at the top of "map" for scripts written against earlier versions (also in "map.quality").
  out["map"]["flipped_faces"] = r.map.quality.flipped_faces;
  out["map"]["conformal_p99"] = wire::json_number(r.map.quality.conformal_p99);
  out["descriptor"] = wire::descriptor_json(r.sh);
  out["timings"] = wire::timings_json(r.timings);
}

// One row for a mesh file; one per kept object for a label volume (format by content; cli/volume_rows.hpp).
void describe_file(const std::string& file, const PipelineOptions& options, const VolumeOptions& volume, bool progress,
                   bool& ok, std::vector<nlohmann::json>& rows) {
  auto fail = [&ok](nlohmann::json& row, const WishError& e) {
    ok = false;
    row["error"] = wire::error_entry_json(e);
  };
  nlohmann::json out = {{"file", file}};
  try {
    const std::string bytes = read_volume_input(file, volume.read);  // a zarr store directory: its zip
    if (detect_volume_format(bytes) != VolumeFormat::Unknown) {
      volume_rows(file, bytes, volume, progress,
                  [&](const volume::VolumeObject&, Mesh mesh) -> std::optional<PipelineResult> {
                    return describe_mesh(std::move(mesh), options);
                  },
                  describe_into, fail, rows);
      return;
    }
    PipelineOptions o = options;
    const auto dot = file.find_last_of('.');
    if (dot != std::string::npos) o.read.hint = format_from_name(file.substr(dot));
    describe_into(out, describe_mesh_bytes(bytes, o));
  } catch (const WishError& e) {
    fail(out, e);
  }
  rows.push_back(std::move(out));
}

// "file" or "file#label_id" for messages.
std::string row_name(const nlohmann::json& r) {
  std::string name = r["file"].get<std::string>();
  if (r.contains("label_id")) name += "#" + std::to_string(r["label_id"].get<std::uint32_t>());
  return name;
}

void print_csv(const std::vector<nlohmann::json>& results, int lmax, std::ostream& os) {
  os << "file,label_id,n_vertices,n_faces,map_method,map_status,fit_mean,fit_rms,fit_max,fit_mean_relative,fit_rms_relative,"
        "fit_max_relative,t_read,t_validate,t_map,t_fit,t_total";
  for (int l = 0; l <= lmax; ++l) os << ",xi_" << l;
  os << "\n" << std::setprecision(17);
  for (const auto& r : results) {
    if (r.contains("error")) continue;
    const auto& d = r["descriptor"];
    const auto& e = d["fit_error"];
    const auto& t = r["timings"];
    std::string file = r["file"].get<std::string>();
    if (file.find_first_of(",\"\n") != std::string::npos) {  // RFC 4180 quoting
      std::string q = "\"";
      for (char c : file) q += c == '"' ? std::string("\"\"") : std::string(1, c);
      file = q + "\"";
    }
    os << file << "," << (r.contains("label_id") ? std::to_string(r["label_id"].get<std::uint32_t>()) : "") << ","
       << r["n_vertices"] << "," << r["n_faces"] << "," << r["map"]["method"].get<std::string>() << ","
       << r["map"]["status"].get<std::string>();
    for (const char* key : {"mean", "rms", "max", "mean_relative", "rms_relative", "max_relative"})
      os << "," << json_number_or_nan(e[key]);
    for (const char* key : {"read", "validate", "map", "fit", "total"}) os << "," << t[key].get<double>();
    for (const auto& xi : d["invariants"]) os << "," << json_number_or_nan(xi);
    os << "\n";
  }
}

void print_table(const nlohmann::json& r, std::ostream& os) {
  os << row_name(r) << ":\n";
  if (r.contains("error")) {
    os << "  error [" << r["error"]["code"].get<std::string>() << "] " << r["error"]["message"].get<std::string>()
       << "\n";
    return;
  }
  const auto& d = r["descriptor"];
  const auto& e = d["fit_error"];
  const auto& t = r["timings"];
  os << std::setprecision(4);
  os << "  vertices / faces     " << r["n_vertices"] << " / " << r["n_faces"] << "\n";
  os << "  map                  " << r["map"]["method"].get<std::string>() << " ("
     << r["map"]["status"].get<std::string>() << ")\n";
  os << "  lmax                 " << d["lmax"] << "\n";
  os << "  fit error mean/rms/max  " << json_number_or_nan(e["mean"]) << " / " << json_number_or_nan(e["rms"]) << " / "
     << json_number_or_nan(e["max"]) << "  (relative to bbox diagonal: " << json_number_or_nan(e["rms_relative"])
     << " rms)\n";
  os << "  invariants xi(l)    ";
  for (const auto& xi : d["invariants"]) os << " " << json_number_or_nan(xi);
  os << "\n  timings [s]          read " << t["read"].get<double>() << ", validate " << t["validate"].get<double>()
     << ", map " << t["map"].get<double>() << ", fit " << t["fit"].get<double>() << ", total "
     << t["total"].get<double>() << "\n";
}

// What the defaults are and how to get the paper's, said where a user looks for it; the recipe is read from core
// (default_recipe.hpp), never restated here.
std::string defaults_footer() {
  const PipelineOptions paper;  // the flow's and the fit's own defaults: the paper's
  std::ostringstream out;
  out << "Defaults: the recipe `wish train` uses when given no options (" << recipe_summary(default_training_recipe())
      << "; chosen by classification accuracy, docs/accuracy.md), so a CSV of `wish describe --csv` trains as\n"
         "`wish train` describes. The paper's map and the closest fit (the most faithful reconstruction, smoother xi\n"
         "classify less well): --method "
      << to_string(paper.map.method) << " --canonical " << to_string(paper.map.canonical.method) << " --lmax "
      << paper.sh.lmax << " --regularization " << paper.sh.regularization << ".";
  return out.str();
}

CommandRunner setup_describe(CLI::App& sub) {
  auto options = std::make_shared<DescribeOptions>();
  const PipelineOptions& defaults = kDefaults;
  sub.add_option("files", options->files, "Mesh files (OBJ, PLY, OFF, STL) or label volumes (NIfTI-1, TIFF, OME-Zarr store or .zip)")->required();
  sub.add_option("--lmax", options->overrides.lmax, "Maximum SH degree")
      ->check(CLI::Range(kShMinFitLmax, kShMaxFitLmax))->default_str(std::to_string(defaults.sh.lmax));
  auto* json = sub.add_flag("--json", options->json, "JSON array, one object per file");
  sub.add_flag("--csv", options->csv, "CSV, one row per mesh, invariants as columns xi_0..xi_L")->excludes(json);
  add_enum_option(sub, "--method", options->overrides.method, kMapMethodNames, defaults.map.method,
                  "Spherical map method");
  sub.add_option("--steps", options->overrides.max_flow_steps,
                 "Step cap of the chosen method's flow (default: willmore " +
                     std::to_string(defaults.map.willmore.max_steps) + ", cmcf " +
                     std::to_string(defaults.map.cmcf.max_steps) + "; not for linear, a single solve)")
      ->check(CLI::PositiveNumber);
  sub.add_option("--area-correction", options->area_correction,
                 "After the conformal map: none (the paper's map) or density_equalizing (area-aware, beyond the paper)")
      ->check(CLI::IsMember({"none", "density_equalizing", "dem"}))->capture_default_str();
  sub.add_option("--canonical", options->canonical,
                 "The map the descriptor is computed on: isometric (the canonical map, relaxed from whichever map the "
                 "chain found: one definition for every mesh, issue 37) | none (the chain's own map)")
      ->check(CLI::IsMember({"none", "isometric"}))->capture_default_str();
  sub.add_option("--sampling", options->sampling,
                 "Where the SH fit samples the surface: surface (quadrature over every face: independent of the "
                 "triangulation) | vertices (the paper)")
      ->check(CLI::IsMember({"vertices", "surface"}))->capture_default_str();
  add_enum_option(sub, "--weights", options->weights, kFitWeightingNames,
                  "Fit weights: input vertex areas or uniform (the paper)");
  add_enum_option(sub, "--solver", options->solver, kFitSolverNames,
                  "direct (one LDLT) or banded (the paper's residual scheme)");
  sub.add_option("--regularization", options->regularization, "nu of the penalty l^2 (l+1)^2 (weights sum to 1)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  sub.add_flag("--quiet", options->quiet, "No progress line for label volumes");
  add_volume_options(sub, options->volume);
  sub.footer(defaults_footer());
  return [options]() {
    check_overrides(options->overrides, "--steps");
    PipelineOptions po = kDefaults;
    apply_overrides(options->overrides, po);
    po.map.area_correction.method = area_correction_from_name(options->area_correction);
    po.map.canonical.method = canonical_map_from_name(options->canonical);
    po.sh.sampling = fit_sampling_from_name(options->sampling);
    po.sh.weighting = options->weights;
    po.sh.solver = options->solver;
    po.sh.regularization = options->regularization;
    bool ok = true;
    std::vector<nlohmann::json> results;
    const VolumeOptions volume = to_volume_options(options->volume);
    for (const auto& file : options->files) {
      const std::size_t first = results.size();
      describe_file(file, po, volume, !options->quiet, ok, results);
      for (std::size_t i = first; i < results.size(); ++i)
        if (!options->json && results[i].contains("error"))
          std::cerr << "wish describe: " << row_name(results[i]) << ": error ["
                    << results[i]["error"]["code"].get<std::string>() << "] "
                    << results[i]["error"]["message"].get<std::string>() << "\n";
    }
    if (options->json)
      std::cout << nlohmann::json(results).dump(2) << "\n";
    else if (options->csv)
      print_csv(results, po.sh.lmax, std::cout);
    else
      for (const auto& r : results)
        if (!r.contains("error")) print_table(r, std::cout);
    return ok ? kExitOk : kExitInvalid;
  };
}

const bool registered = register_command(
    {"describe", "Spherical-harmonic descriptor of meshes: map, fit, invariants, fit error, timings", &setup_describe, 30});

}  // namespace
}  // namespace wish::cli::describe_command
