// `wish demo-data --out DIR --per-class N --seed S`: writes the SYNTHETIC demo set (core/synth/demo_dataset.hpp)
// as DIR/<class>/<class>_<index>.ply (binary PLY, µm), one sub-directory per class — the layout `wish train`
// reads. Same seed, same bytes.
#include <filesystem>
#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>

#include "cli/command_registry.hpp"
#include "core/io/mesh_io.hpp"
#include "core/synth/demo_dataset.hpp"

namespace wish::cli::demo_data_command {  // one namespace per command: the commands compile in one unity batch
namespace {

struct DemoDataOptions {
  std::string out;
  int per_class = 16;
  std::uint64_t seed = 1;
  double voxel_size = synth::DemoOptions{}.voxel_size;
  bool quiet = false;
};

CommandRunner setup_demo_data(CLI::App& sub) {
  auto o = std::make_shared<DemoDataOptions>();
  sub.add_option("--out", o->out, "Output directory (one sub-directory per class)")->required();
  sub.add_option("--per-class", o->per_class, "Meshes per class")->check(CLI::Range(1, 10000))->capture_default_str();
  sub.add_option("--seed", o->seed, "Random seed (same seed: identical files)")->capture_default_str();
  sub.add_option("--voxel-size", o->voxel_size, "Label-volume voxel size in µm (smaller: more vertices)")
      ->check(CLI::Range(0.05, 2.0))->capture_default_str();
  sub.add_flag("--quiet", o->quiet, "No progress on stderr");
  return [o]() {
    synth::DemoOptions options;
    options.per_class = o->per_class;
    options.seed = o->seed;
    options.voxel_size = o->voxel_size;
    const auto& classes = synth::demo_classes();
    long total_vertices = 0, min_v = -1, max_v = 0, count = 0;
    for (int i = 0; i < options.per_class; ++i)
      for (int c = 0; c < static_cast<int>(classes.size()); ++c) {
        const synth::DemoMesh d = synth::generate_demo_nucleus(c, i, options);
        const std::filesystem::path dir = std::filesystem::path(o->out) / d.label;
        std::filesystem::create_directories(dir);
        write_mesh_file(d.mesh, dir / (d.name + ".ply"), MeshEncoding::BinaryLittleEndian);
        const long v = static_cast<long>(d.mesh.vertex_count());
        total_vertices += v;
        min_v = min_v < 0 ? v : std::min(min_v, v);
        max_v = std::max(max_v, v);
        ++count;
        if (!o->quiet)
          std::cerr << "[" << count << "/" << options.per_class * classes.size() << "] " << (dir / (d.name + ".ply")).string()
                    << ": " << v << " vertices, " << d.mesh.face_count() << " faces"
                    << (d.attempts > 1 ? " (attempt " + std::to_string(d.attempts) + ")" : "") << "\n";
      }
    std::cout << "wrote " << count << " SYNTHETIC meshes (" << classes.size() << " classes x " << options.per_class
              << ", seed " << options.seed << ") to " << o->out << "; vertices " << min_v << ".." << max_v << ", mean "
              << total_vertices / std::max(count, 1L) << "\n";
    return kExitOk;
  };
}

const bool registered = register_command(
    {"demo-data", "Write the deterministic SYNTHETIC demo set of nucleus-like meshes (six classes)", &setup_demo_data, 80});

}  // namespace
}  // namespace wish::cli::demo_data_command
