// Slow sweep (label "slow"): every closed genus-0 mesh in ../shared/data gets a verified bijective map, or a
// reported failure that the fallback chain then fixes. Prints one line per mesh.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/io/mesh_io.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/validation/mesh_report.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

std::vector<std::filesystem::path> sweep_meshes(const std::filesystem::path& root) {
  std::vector<std::filesystem::path> out = testing::files_in(root / "cgal" / "genus0_closed", {".off", ".ply", ".obj"});
  for (const char* q : {"hq", "lq"})
    for (const auto& p : testing::files_in(root / "nmv_nuclei" / "nuclei-meshes" / q, {".obj"})) out.push_back(p);
  if (std::filesystem::exists(root / "celegans_cell" / "cell.obj")) out.push_back(root / "celegans_cell" / "cell.obj");
  return out;
}

TEST(SharedMeshSweep, EveryClosedGenus0MeshGetsAVerifiedMap) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const auto root = *testing::shared_data_dir();
  const auto meshes = sweep_meshes(root);
  ASSERT_GE(meshes.size(), 40u);
  int fixed_by_fallback = 0;
  for (const auto& path : meshes) {
    const std::string name = std::filesystem::relative(path, root).string();
    SCOPED_TRACE(name);
    PreparedMesh prepared = prepare_for_mapping(read_mesh_file(path).mesh);
    ASSERT_TRUE(prepared.mappable()) << prepared.issues.front().message;
    const auto t0 = std::chrono::steady_clock::now();
    const SphericalMapResult r = compute_spherical_map(prepared.mesh);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const MapAttempt& first = r.attempts.front();
    int steps = 0;
    for (const auto& a : r.attempts) steps += static_cast<int>(a.steps.size());
    std::printf("[sweep] %-44s V=%6ld %-8s attempts=%zu steps=%3d flips=%ld K mean/p99=%.3f/%.3f R=%.1e %6.2fs %s%s\n",
                name.c_str(), static_cast<long>(prepared.mesh.vertex_count()), to_string(r.method_used), r.attempts.size(),
                steps, r.quality.flipped_faces, r.quality.conformal_mean, r.quality.conformal_p99, r.quality.roundness,
                seconds, to_string(r.status),
                first.status == MapStatus::Ok ? "" : (" (first: " + std::string(to_string(first.status)) + " " +
                                                      first.failed_check + ")").c_str());
    std::fflush(stdout);
    EXPECT_TRUE(r.ok()) << r.failed_check << ": " << r.attempts.back().message;
    EXPECT_EQ(r.quality.flipped_faces, 0);
    EXPECT_EQ(r.quality.degree, 1);
    if (first.status != MapStatus::Ok) {
      EXPECT_FALSE(first.failed_check.empty());  // a failure is always named
      ++fixed_by_fallback;
    }
  }
  std::printf("[sweep] %zu meshes, %d needed the fallback\n", meshes.size(), fixed_by_fallback);
}

}  // namespace
}  // namespace wish
