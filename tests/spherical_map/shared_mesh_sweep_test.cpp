// Slow sweep: every closed genus-0 mesh in ../shared/data gets a verified bijective map (0 flipped, 0 degenerate
// faces, degree 1) through the fallback chain (docs/design/spherical-map.md §7). The nuclei and the C. elegans cell — the
// meshes the paper is about — must get a Willmore map on the FIRST attempt. Prints one line per mesh and one per
// attempt. WISH_SWEEP_FILTER=substring restricts the sweep to matching paths (for debugging one mesh).
//   OPENBLAS_NUM_THREADS=1 build/flow/tests/spherical_map_shared_mesh_sweep_test
#include <chrono>
#include <cstdio>
#include <cstdlib>
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

// Meshes that defeat every method of the chain, reported to the lead with their figures (printed by this test).
// Nothing is asserted for them beyond the printed figures (and that they still fail: remove them when fixed).
// Distortion is no failure any more (a verdict); bull, cow, man, part (K p99 6-9) and camel (cMCF, 0 flips after the
// mollified operator) now pass.
struct KnownFailure {
  const char* name;
  const char* why;
};
// oblong (needle/fan CAD mesh, 2-3 flips in every method) passes since the chart untangling (chart_untangle.hpp):
// cMCF + repair, K p99 ~280 (distorted).
const std::vector<KnownFailure> kKnownFailures = {};

const KnownFailure* known_failure(const std::string& name) {
  for (const auto& k : kKnownFailures)
    if (name.find(k.name) != std::string::npos) return &k;
  return nullptr;
}

TEST(SharedMeshSweep, EveryClosedGenus0MeshGetsAVerifiedMap) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const auto root = *testing::shared_data_dir();
  const char* filter = std::getenv("WISH_SWEEP_FILTER");
  const auto meshes = sweep_meshes(root);
  if (!filter) {
    ASSERT_GE(meshes.size(), 40u);
  }
  int fixed_by_fallback = 0, swept = 0;
  std::vector<std::string> distorted;  // accepted with the verdict "distorted"
  const auto t_sweep = std::chrono::steady_clock::now();
  for (const auto& path : meshes) {
    const std::string name = std::filesystem::relative(path, root).string();
    if (filter && name.find(filter) == std::string::npos) continue;
    ++swept;
    SCOPED_TRACE(name);
    PreparedMesh prepared = prepare_for_mapping(read_mesh_file(path).mesh);
    ASSERT_TRUE(prepared.mappable()) << prepared.issues.front().message;
    const auto t0 = std::chrono::steady_clock::now();
    // No flow budget here: this test is about correctness on a shared, loaded machine, where a wall-clock budget
    // would cut the nuclei's Willmore flows; the time is measured by bench/map_collection_bench.
    SphericalMapOptions options;
    options.flow_budget_seconds = 0;
    options.chain_budget_seconds = 0;
    const SphericalMapResult r = compute_spherical_map(prepared.mesh, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const MapAttempt& first = r.attempts.front();
    if (r.verdict == MapVerdict::Distorted) distorted.push_back(name + " K p99 " + std::to_string(r.quality.conformal_p99));
    int steps = 0;
    for (const auto& a : r.attempts) steps += static_cast<int>(a.steps.size());
    std::printf("[sweep] %-44s V=%6ld %-8s attempts=%zu steps=%3d flips=%ld degen=%ld minA=%.1e K mean/p99=%.3f/%.3f "
                "R=%.1e %6.2fs %s%s\n",
                name.c_str(), static_cast<long>(prepared.mesh.vertex_count()), to_string(r.method_used),
                r.attempts.size(), steps, r.quality.flipped_faces, r.quality.degenerate_faces, r.quality.min_face_area,
                r.quality.conformal_mean, r.quality.conformal_p99, r.quality.roundness, seconds, to_string(r.status),
                first.status == MapStatus::Ok ? "" : (" (first: " + std::string(to_string(first.status)) + " " +
                                                      to_string(first.failed_check) + ")").c_str());
    if (r.attempts.size() > 1 || std::getenv("WISH_SWEEP_STEPS"))
      for (size_t k = 0; k < r.attempts.size(); ++k) {
        const MapAttempt& a = r.attempts[k];
        std::printf("[sweep]    attempt %zu %-8s%s steps=%3zu flips=%ld degen=%ld repaired=%ld minH=%.1e K p99=%.3f "
                    "R=%.1e %6.2fs %s %s\n",
                    k, to_string(a.method), a.filtered ? " (filt)" : "       ", a.steps.size(), a.quality.flipped_faces,
                    a.quality.degenerate_faces, a.quality.repaired_vertices, a.quality.min_face_height,
                    a.quality.conformal_p99, a.quality.roundness,
                    a.seconds, to_string(a.status), to_string(a.failed_check));
        if (std::getenv("WISH_SWEEP_STEPS"))
          for (const FlowStepRecord& s : a.steps)
            std::printf("[sweep]       step %2d tau %.3f E/4pi %.5f R %.2e %s %s\n", s.step, s.tau,
                        s.energy / (4 * 3.141592653589793), s.roundness, s.accepted ? "ok " : "rej", s.note.c_str());
      }
    std::fflush(stdout);
    if (first.status != MapStatus::Ok) {
      EXPECT_NE(first.failed_check, MapCheck::None);  // a failure is always named
      ++fixed_by_fallback;
    }
    const bool paper_mesh = name.find("nmv_nuclei") != std::string::npos || name.find("celegans_cell") != std::string::npos;
    if (paper_mesh) {
      EXPECT_EQ(first.status, MapStatus::Ok) << "nuclei and the cell must map on the first attempt: "
                                             << to_string(first.failed_check) << ": " << first.message;
      EXPECT_EQ(first.method, MapMethod::Willmore);
    }
    if (const KnownFailure* known = known_failure(name)) {
      std::printf("[sweep]    KNOWN FAILURE %s (%s): returned %s [%s], flips %ld, degenerate %ld, degree %d, K p99 %.2f\n",
                  name.c_str(), known->why, to_string(r.status), to_string(r.failed_check), r.quality.flipped_faces,
                  r.quality.degenerate_faces, r.quality.degree, r.quality.conformal_p99);
      EXPECT_FALSE(r.ok()) << "a known failure now passes: remove it from kKnownFailures";
      continue;
    }
    EXPECT_TRUE(r.ok()) << to_string(r.failed_check) << ": " << r.attempts[static_cast<size_t>(r.chosen_attempt)].message;
    EXPECT_NE(r.verdict, MapVerdict::Failed);
    EXPECT_EQ(r.quality.flipped_faces, 0);
    EXPECT_EQ(r.quality.degenerate_faces, 0);
    EXPECT_EQ(r.quality.non_finite_vertices, 0);
    EXPECT_EQ(r.quality.degree, 1);
    EXPECT_EQ(r.sphere.rows(), prepared.mesh.vertex_count());
    EXPECT_LT(r.quality.mobius_centroid, 1e-8);
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_sweep).count();
  std::printf("[sweep] %d meshes, %d needed the fallback, %.1f s\n", swept, fixed_by_fallback, total);
  std::printf("[sweep] %zu accepted with the verdict distorted:\n", distorted.size());
  for (const std::string& d : distorted) std::printf("[sweep]    %s\n", d.c_str());
}

}  // namespace
}  // namespace wish
