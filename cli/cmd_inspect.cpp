// `wish inspect FILE... [--json]`: reads each mesh, repairs the harmless defects and reports whether it can be
// mapped to the sphere. Exit status 0 when every file is valid and mappable, 1 otherwise (a file that cannot be read
// counts as invalid and is reported in line, so one bad file does not hide the others).
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/command_registry.hpp"
#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"
#include "core/validation/mesh_report.hpp"
#include "wire/error_json.hpp"
#include "wire/wire_json.hpp"

namespace wish::cli::inspect_command {  // one namespace per command: the commands compile in one unity batch
namespace {

using wire::json_number_or_nan;

struct InspectOptions {
  std::vector<std::string> files;
  bool json = false;
};

// One file: {"file", "valid", and either "error" or "encoding", "mesh" (the service's MeshBlock: format, bytes,
// read_notes, input and prepared reports, repairs) and "issues"}. Every block uses the wire encoders
// (wire/wire_json.hpp, wire/error_json.hpp), so a file inspected here reads like the service's answer.
nlohmann::json inspect_file(const std::string& file) {
  nlohmann::json out = {{"file", file}};
  try {
    const ReadResult read = read_mesh_file(file);
    const PreparedMesh prepared = prepare_for_mapping(read.mesh);
    out["valid"] = prepared.mappable();
    out["encoding"] = read.encoding == MeshEncoding::Ascii ? "ascii"
                      : read.encoding == MeshEncoding::BinaryBigEndian ? "binary_big_endian" : "binary_little_endian";
    out["mesh"] = wire::mesh_block_json(prepared, read.format, std::filesystem::file_size(file), read.notes);
    out["issues"] = nlohmann::json::array();
    for (const auto& i : prepared.issues) out["issues"].push_back(wire::issue_json(i));
  } catch (const WishError& e) {
    out["valid"] = false;
    out["error"] = wire::error_entry_json(e);
  }
  return out;
}

void print_table(const nlohmann::json& result, std::ostream& os) {
  os << result["file"].get<std::string>() << ": " << (result["valid"].get<bool>() ? "VALID (mappable)" : "INVALID") << "\n";
  if (result.contains("error")) {
    os << "  error [" << result["error"]["code"].get<std::string>() << "] " << result["error"]["message"].get<std::string>() << "\n";
    return;
  }
  const auto& mesh = result["mesh"];
  const auto& r = mesh["prepared"];
  const auto row = [&](const char* label, const std::string& value) { os << "  " << std::left << std::setw(27) << label << value << "\n"; };
  const auto num = [&](const char* key) { return r[key].dump(); };
  row("format", mesh["format"].get<std::string>() + " (" + result["encoding"].get<std::string>() + ")");
  row("vertices / edges / faces", num("vertices") + " / " + num("edges") + " / " + num("faces"));
  row("components", num("components"));
  row("boundary edges", num("boundary_edges"));
  row("non-manifold edges", num("nonmanifold_edges"));
  row("non-manifold vertices", num("nonmanifold_vertices"));
  row("Euler characteristic", num("euler_characteristic"));
  row("genus", r["genus"].is_null() ? "n/a" : num("genus"));
  row("degenerate faces", num("degenerate_faces"));
  row("duplicate faces", num("duplicate_faces"));
  row("unreferenced vertices", num("unreferenced_vertices"));
  row("duplicate vertices", num("duplicate_vertices"));
  row("consistently oriented", r["orientation_consistent"].get<bool>() ? "yes" : "no (" + num("misoriented_edges") + " edges)");
  std::ostringstream geometry;
  geometry << std::setprecision(6) << json_number_or_nan(r["signed_volume"]) << " / " << json_number_or_nan(r["area"]);
  row("signed volume / area", geometry.str());
  std::ostringstream box;
  const auto xyz = [&](const nlohmann::json& v) {
    box << "[" << json_number_or_nan(v[0]) << ", " << json_number_or_nan(v[1]) << ", " << json_number_or_nan(v[2]) << "]";
  };
  box << std::setprecision(6);
  xyz(r["bbox_min"]);
  box << " - ";
  xyz(r["bbox_max"]);
  row("bounding box", box.str());
  for (const auto& note : mesh["read_notes"]) os << "  note:   " << note.get<std::string>() << "\n";
  for (const auto& repair : mesh["repairs"])
    os << "  repair: [" << repair["code"].get<std::string>() << "] " << repair["message"].get<std::string>() << "\n";
  for (const auto& issue : result["issues"])
    os << "  issue:  [" << issue["code"].get<std::string>() << "] " << issue["message"].get<std::string>() << "\n";
}

CommandRunner setup_inspect(CLI::App& sub) {
  auto options = std::make_shared<InspectOptions>();
  sub.add_option("files", options->files, "Mesh files (OBJ, PLY, OFF, STL; format detected from the content)")->required();
  sub.add_flag("--json", options->json, "Print a JSON array with one object per file instead of a table");
  return [options]() {
    nlohmann::json all = nlohmann::json::array();
    bool all_valid = true;
    for (const auto& file : options->files) {
      nlohmann::json result = inspect_file(file);
      all_valid = all_valid && result["valid"].get<bool>();
      if (!options->json) print_table(result, std::cout);
      all.push_back(std::move(result));
    }
    if (options->json) std::cout << all.dump(2) << "\n";
    return all_valid ? kExitOk : kExitInvalid;
  };
}

const bool registered = register_command(
    {"inspect", "Report the topology and geometry of mesh files and whether they can be mapped to the sphere", &setup_inspect, 10});

}  // namespace
}  // namespace wish::cli::inspect_command
