// What removing the handles does to genus >= 1 objects (issue 39, core/volume/topology_repair.hpp): the UroCell
// complete objects (>= 500 voxels, not touching the border; mito, lyso, fv; ../shared/data/urocell) and generated
// masks of touching spheres (objects = 6-connected components of the mask: spheres touching in a loop form a handle).
// For each object with a handle: its genus, the voxels touching another object, the voxels that cutting every handle
// and filling every tunnel would change, the repair chosen (each handle cut or filled, whichever changes less) and its
// volume change (in % of the object's voxels), and whether the default bound keeps it. The table goes to
// docs/accuracy.md ("Handles"); it is what the default `max_repair_share` was chosen from.
//   build/release/bench/handle_repair_bench [UROCELL_DIR]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/io/volume_io.hpp"
#include "core/volume/label_objects.hpp"
#include "core/volume/object_surface.hpp"

namespace fs = std::filesystem;
using namespace wish;
using namespace wish::volume;

namespace {

struct Row {
  std::string collection, volume;
  std::uint32_t id = 0;
  std::int64_t voxels = 0;
  int genus = 0, pieces = 1;
  std::int64_t touching = 0;
  std::size_t touching_objects = 0;
  TopologyRepairFigures repair;
};

SurfaceOptions probe_options() {
  SurfaceOptions o;
  o.max_repair_share = 0;      // never kept: the figures of the repair are measured all the same
  o.smoothing_iterations = 0;  // only the voxel surface matters here
  o.target_vertices = 0;
  return o;
}

void measure(const std::string& collection, const std::string& volume, const LabelImage& image, const ObjectOptions& oo,
             std::vector<Row>& rows, int& objects) {
  const ObjectSet set = find_objects(image, oo);
  for (const VolumeObject& o : set.objects) {
    ++objects;
    const ObjectSurface s = object_surface(image, set, o, probe_options());
    if (s.genus <= 0 && collection != "spheres") continue;  // every generated mask is listed, handle or not
    rows.push_back({collection, volume, o.id, o.voxel_count, s.genus, s.pieces, s.touching_voxels, s.touching_ids.size(),
                    s.repair});
  }
}

// Spheres of radius r (voxels) with centres `centres`, all one mask value.
LabelImage spheres(const std::vector<Eigen::Vector3d>& centres, double r) {
  LabelImage image;
  image.dims = {64, 64, 40};
  image.labels.assign(static_cast<std::size_t>(image.voxel_count()), 0);
  for (std::int64_t z = 0; z < image.dims[2]; ++z)
    for (std::int64_t y = 0; y < image.dims[1]; ++y)
      for (std::int64_t x = 0; x < image.dims[0]; ++x)
        for (const auto& c : centres)
          if ((Eigen::Vector3d(static_cast<double>(x), static_cast<double>(y), static_cast<double>(z)) - c).norm() <= r)
            image.labels[image.index(x, y, z)] = 255;
  return image;
}

// n spheres of radius r on a circle in the z = 20 plane, neighbours' centres 2r − overlap apart (a ring of cells).
LabelImage ring(int n, double r, double overlap) {
  const double pi = std::acos(-1.0);
  const double d = 2 * r - overlap, radius = d / (2 * std::sin(pi / n));
  std::vector<Eigen::Vector3d> centres;
  for (int k = 0; k < n; ++k)
    centres.emplace_back(32 + radius * std::cos(2 * pi * k / n) + 0.31, 32 + radius * std::sin(2 * pi * k / n) + 0.17, 20.23);
  return spheres(centres, r);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<Row> rows;
  int objects = 0;
  const fs::path root = argc > 1 ? fs::path(argv[1]) : fs::path(WISH_SHARED_DATA_DEFAULT) / "urocell";
  ObjectOptions complete;
  complete.min_voxels = 500;  // the complete objects of docs/accuracy.md
  complete.drop_truncated = true;
  for (const char* sub : {"mito/instance", "lyso/binary", "fv/instance"}) {
    if (!fs::exists(root / sub)) continue;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(root / sub)) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files)
      measure(std::string(sub).substr(0, std::string(sub).find('/')), f.filename().string(), read_volume_file(f).image,
              complete, rows, objects);
  }
  const int urocell_objects = objects;
  ObjectOptions all;
  for (int n : {3, 4, 6})
    for (double r : {6.0, 8.0})
      for (double overlap : {1.0, 2.0, 3.0}) {
        char name[64];
        std::snprintf(name, sizeof name, "ring of %d, r %.0f, overlap %.0f", n, r, overlap);
        measure("spheres", name, ring(n, r, overlap), all, rows, objects);
      }
  std::printf("objects measured: %d UroCell complete objects, %d generated touching-sphere masks\n\n", urocell_objects,
              objects - urocell_objects);
  const double bound = SurfaceOptions::kDefaultMaxRepairShare;
  std::printf("| collection | volume | object | voxels | genus | touching voxels (objects) | cut every handle | fill every tunnel | repair | volume change | kept by default (<= %.0f %%) |\n",
              100 * bound);
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---|---:|---|\n");
  int kept = 0, with_handles = 0;
  for (const Row& r : rows) {
    const bool handles = r.genus > 0;
    with_handles += handles;
    kept += handles && r.repair.volume_change() <= bound;
    std::printf("| %s | %s | %u | %lld | %d | %lld (%zu) | %s | %s | %s | %s | %s |\n", r.collection.c_str(),
                r.volume.c_str(), r.id, static_cast<long long>(r.voxels), r.genus, static_cast<long long>(r.touching),
                r.touching_objects, handles ? std::to_string(r.repair.cut_every_handle).c_str() : "-",
                handles ? std::to_string(r.repair.fill_every_tunnel).c_str() : "-",
                handles ? (r.repair.describe().substr(0, r.repair.describe().find(": genus"))).c_str() : "-",
                handles ? (std::to_string(std::round(r.repair.volume_change() * 10000) / 100).substr(0, 5) + " %").c_str() : "-",
                handles ? (r.repair.volume_change() <= bound ? "yes" : "no") : "-");
  }
  std::printf("\n%d objects with handles, %d repaired by default\n", with_handles, kept);
  return 0;
}
