// `wish reconstruct DESCRIPTOR.json [--level 5] --out shape.ply [--index I]`: evaluates the SH surface of a
// descriptor (wire/wire_json.hpp layout: one entry / the I-th entry of `wish describe --json` output, or a
// /v1/describe response with include=coefficients) on a subdivided icosahedron (level 0..7: 10*4^level + 2
// vertices) and writes it (format from the extension: .ply binary, .obj, .off, .stl).
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/command_registry.hpp"
#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"
#include "core/sh/sh_reconstruction.hpp"
#include "wire/wire_json.hpp"

namespace wish::cli::reconstruct_command {  // one namespace per command: the commands compile in one unity batch
namespace {

struct ReconstructOptions {
  std::string descriptor, out;
  int level = 5;
  int index = -1;
};

CommandRunner setup_reconstruct(CLI::App& sub) {
  auto options = std::make_shared<ReconstructOptions>();
  sub.add_option("descriptor", options->descriptor, "Descriptor JSON (from wish describe --json, or /v1/describe with include=coefficients)")->required();
  sub.add_option("--level", options->level, "Icosphere subdivision level")->check(CLI::Range(0, 7))->capture_default_str();
  sub.add_option("--out", options->out, "Output mesh (.ply, .obj, .off, .stl)")->required();
  sub.add_option("--index", options->index, "Entry of a describe --json array (default: the only entry)");
  return [options]() {
    std::ifstream in(options->descriptor);
    if (!in) throw IoError("file_not_found", "cannot open '" + options->descriptor + "'");
    nlohmann::json json;
    try {
      json = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
      throw InvalidInputError("invalid_descriptor", std::string("descriptor is not JSON: ") + e.what());
    }
    if (json.is_array()) {
      if (options->index < 0 && json.size() != 1)
        throw InvalidInputError("invalid_parameter", "the file holds " + std::to_string(json.size()) +
                                                         " descriptors; choose one with --index");
      const size_t i = options->index < 0 ? 0 : size_t(options->index);
      if (i >= json.size()) throw InvalidInputError("invalid_parameter", "--index is out of range");
      json = json[i];
    }
    if (json.is_object() && json.contains("error"))
      throw InvalidInputError("invalid_descriptor", "the selected entry is a failed describe result");
    const ShDescriptor d = wire::descriptor_from_json(json);
    const Mesh mesh = reconstruct_on_icosphere(d, options->level);
    write_mesh_file(mesh, options->out);
    std::cout << "wrote " << options->out << ": " << mesh.vertex_count() << " vertices, " << mesh.face_count()
              << " faces (lmax " << d.lmax << ", icosphere level " << options->level << ")\n";
    return kExitOk;
  };
}

const bool registered = register_command(
    {"reconstruct", "Evaluate a descriptor's SH surface on an icosphere and write the mesh", &setup_reconstruct, 40});

}  // namespace
}  // namespace wish::cli::reconstruct_command
