// Writes the hard closed genus-0 shapes of tests/synth/hard_shapes.hpp as binary PLY (exact doubles), one folder per
// family and tessellation (coil/, coil_needle/, dumbbell/, ...), so that map_collection_bench runs the DEFAULT map
// chain over them (read -> prepare_for_mapping -> compute_spherical_map) and prints one row per family:
//   hard_shapes_export OUTDIR && map_collection_bench OUTDIR/*
// Per shape it prints (stdout) the vertex count, the needle statistics (triangles with an angle under 5 degrees,
// longest / median edge) and the generation time.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/io/mesh_io.hpp"
#include "tests/synth/hard_shapes.hpp"

int main(int argc, char** argv) {
  if (argc != 2 || std::string(argv[1]).starts_with("-")) {
    std::fprintf(stderr, "usage: %s OUTDIR\n", argv[0]);
    return 2;
  }
  const std::filesystem::path out = argv[1];
  std::printf("| shape | tessellation | V | angle < 5 deg | longest / median edge | generation s |\n|---|---|---|---|---|---|\n");
  for (const auto& shape : wish::testing::hard_shape_catalogue()) {
    const bool needle = shape.tessellation == wish::testing::Tessellation::NeedleHeavy;
    const auto t0 = std::chrono::steady_clock::now();
    const wish::Mesh mesh = wish::testing::mesh_solid(shape.solid, wish::testing::recipe_for(shape.tessellation));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto stats = wish::testing::needle_stats(mesh);
    std::string file = shape.name + ".ply";
    for (char& c : file)
      if (c == ' ' || c == ',' || c == ':' || c == '/') c = '_';
    const std::filesystem::path dir = out / (shape.family + (needle ? "_needle" : ""));
    std::filesystem::create_directories(dir);
    wish::write_mesh_file(mesh, dir / file);
    std::printf("| %s | %s | %ld | %.1f %% | %.1f | %.1f |\n", shape.name.c_str(), needle ? "needle-heavy" : "fine",
                static_cast<long>(mesh.vertex_count()), 100 * stats.small_angle_share, stats.longest_over_median_edge, seconds);
    std::fflush(stdout);
  }
  return 0;
}
