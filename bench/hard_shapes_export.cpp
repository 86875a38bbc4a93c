// Writes the hard closed genus-0 shapes of tests/synth/hard_shapes.hpp as binary PLY (exact doubles), one folder per
// family and tessellation (coil/, coil_needle/, dumbbell/, ...), so that map_collection_bench runs the DEFAULT map
// chain over them (read -> prepare_for_mapping -> compute_spherical_map) and prints one row per family:
//   hard_shapes_export OUTDIR && map_collection_bench OUTDIR/*
// then the needle-heavy spine variants (needle_spine_variants) in spine_variant_needle/; --spines-only writes only the
// needle-heavy spines (those and the catalogue's two in mushroom_spine_needle/).
// Per shape it prints (stdout) the vertex count, the needle statistics (triangles with an angle under 5 degrees,
// longest / median edge) and the generation time.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/io/mesh_io.hpp"
#include "tests/synth/hard_shapes.hpp"

int main(int argc, char** argv) {
  const bool spines_only = argc == 3 && std::string(argv[1]) == "--spines-only";
  if (!(argc == 2 || spines_only) || std::string(argv[argc - 1]).starts_with("-")) {
    std::fprintf(stderr, "usage: %s [--spines-only] OUTDIR\n", argv[0]);
    return 2;
  }
  const std::filesystem::path out = argv[argc - 1];
  std::printf("| shape | tessellation | V | angle < 5 deg | longest / median edge | generation s |\n|---|---|---|---|---|---|\n");
  // The catalogue (fine and needle-heavy), then the needle-heavy spine variants (folder spine_variant_needle/).
  // With --spines-only, the needle-heavy spines alone.
  std::vector<wish::testing::HardShape> shapes;
  for (auto& shape : wish::testing::hard_shape_catalogue())
    if (!spines_only || (shape.family == "mushroom_spine" && shape.tessellation == wish::testing::Tessellation::NeedleHeavy))
      shapes.push_back(std::move(shape));
  const std::size_t catalogue_size = shapes.size();
  for (auto& shape : wish::testing::needle_spine_variants()) shapes.push_back(std::move(shape));
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const auto& shape = shapes[k];
    const bool needle = shape.tessellation == wish::testing::Tessellation::NeedleHeavy;
    const auto t0 = std::chrono::steady_clock::now();
    const wish::testing::MeshingRecipe recipe =
        k < catalogue_size ? wish::testing::recipe_for(shape.tessellation) : wish::testing::needle_spine_recipe();
    const wish::Mesh mesh = wish::testing::mesh_solid(shape.solid, recipe);
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
