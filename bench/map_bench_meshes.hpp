#pragma once
// The meshes the spherical-map benchmarks share, so their tables line up row for row: the NeuroMorphoVis nucleus
// nmv_nuclei/hq/nucleus-1.obj (10.8K vertices; skipped without the shared data) and bumpy ellipsoids on icospheres
// of level 4..7 (2562, 10242, 40962, 163842 vertices).

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "core/io/mesh_io.hpp"
#include "core/mesh/icosphere.hpp"
#include "core/validation/mesh_report.hpp"

namespace wish::bench {

struct BenchMesh {
  std::string name;
  Mesh mesh;
};

// A smooth genus-0 shape of any resolution: axes 1 : 0.75 : 0.6 with a 6 % low-frequency radial bump.
inline Mesh bumpy_ellipsoid(int level) {
  Mesh m = make_icosphere(level);
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i) {
    const Eigen::Vector3d p = m.vertices.row(i);
    const double r = 1.0 + 0.06 * std::sin(5 * p.x() + 0.3) * std::sin(4 * p.y()) * std::cos(3 * p.z());
    m.vertices.row(i) = (r * p).cwiseProduct(Eigen::Vector3d(1.0, 0.75, 0.6)).transpose();
  }
  return m;
}

// Bumpy ellipsoids of levels first_level..7, with the nucleus placed after the level-4 one (by size).
inline std::vector<BenchMesh> map_bench_meshes(int first_level) {
  std::filesystem::path shared = WISH_SHARED_DATA_DEFAULT;
  if (const char* env = std::getenv("WISH_SHARED_DATA")) shared = env;
  const auto nucleus = shared / "nmv_nuclei" / "nuclei-meshes" / "hq" / "nucleus-1.obj";
  std::vector<BenchMesh> meshes;
  for (int level = first_level; level <= 7; ++level) {
    if (level == 5 && std::filesystem::exists(nucleus))
      meshes.push_back({"nucleus-1 (hq)", prepare_for_mapping(read_mesh_file(nucleus).mesh).mesh});
    meshes.push_back({"bumpy-ico" + std::to_string(level), bumpy_ellipsoid(level)});
  }
  return meshes;
}

}  // namespace wish::bench
