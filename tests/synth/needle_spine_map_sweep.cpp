// The default map chain (as `wish map` / `wish describe` run it: prepare_for_mapping, then compute_spherical_map with
// the default options) on the decimated, needle-heavy dendritic spines of the generator (tests/synth/hard_shapes.hpp:
// needle_spine_variants and the catalogue's two needle-heavy mushroom spines): every one gets a verified bijective
// map; the needle retry and choice (map_chain.cpp) make more of them end on a flow (Willmore or cMCF, not the linear
// map or the progressive embedding) and change no map that ended on a flow without them. Issue 24 item 3 asks for
// >= 90 % on a flow (13 of 14): measured 13 of 14 since the retry's kernel placement (star_kernel_repair.hpp) and
// its deferred run after the linear map (5 without the retry and choice; 7 with them before); the floor asserted
// here is the measured figure, so a regression shows (docs/design/needle-flows.md). Slow: 14 meshes voxelised,
// decimated and mapped (about a minute).
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/spherical_map/spherical_map.hpp"
#include "core/validation/mesh_report.hpp"
#include "tests/synth/hard_shapes.hpp"

namespace wish::testing {
namespace {

struct SpineMesh {
  std::string name;
  Mesh mesh;
};

std::vector<SpineMesh> needle_spines() {
  std::vector<SpineMesh> out;
  for (const HardShape& s : hard_shape_catalogue())
    if (s.family == "mushroom_spine" && s.tessellation == Tessellation::NeedleHeavy)
      out.push_back({s.name, mesh_solid(s.solid, recipe_for(s.tessellation))});
  for (const HardShape& s : needle_spine_variants()) out.push_back({s.name, mesh_solid(s.solid, needle_spine_recipe())});
  return out;
}

bool is_flow(MapMethod m) { return m == MapMethod::Willmore || m == MapMethod::Cmcf; }

TEST(SlowNeedleSpines, EveryMapIsBijectiveAndTheNeedleRetryEndsMoreOnAFlowChangingNoFlowMap) {
  const std::vector<SpineMesh> spines = needle_spines();
  ASSERT_EQ(spines.size(), 14u);
  int on_flow = 0, on_flow_without_retry = 0;
  for (const SpineMesh& s : spines) {
    SCOPED_TRACE(s.name);
    const PreparedMesh p = prepare_for_mapping(s.mesh);
    ASSERT_TRUE(p.mappable());
    const SphericalMapResult r = compute_spherical_map(p.mesh);
    SphericalMapOptions without;
    without.needle_aware = false;
    const SphericalMapResult before = compute_spherical_map(p.mesh, without);
    const NeedleStats n = needle_stats(s.mesh);
    std::printf("[needle spine] %-44s V %4ld  angle<5 %4.1f %%  edge ratio %5.1f  ended on %-8s%s K p99 %7.2f  "
                "(without the retry: %s, K p99 %.2f)\n",
                s.name.c_str(), static_cast<long>(s.mesh.vertex_count()), 100 * n.small_angle_share,
                n.longest_over_median_edge, to_string(r.method_used),
                r.attempts[static_cast<size_t>(r.chosen_attempt)].needle ? " (needle)" : "         ",
                r.quality.conformal_p99, to_string(before.method_used), before.quality.conformal_p99);
    EXPECT_TRUE(r.ok()) << to_string(r.failed_check);
    EXPECT_EQ(r.quality.flipped_faces, 0);
    EXPECT_EQ(r.quality.degenerate_faces, 0);
    EXPECT_EQ(r.quality.degree, 1);
    // A needle retry's map repaired by the kernel placement says so (its moves are part of the repaired vertices).
    const MapAttempt& chosen = r.attempts[static_cast<size_t>(r.chosen_attempt)];
    EXPECT_LE(chosen.kernel_placed_vertices, chosen.quality.repaired_vertices);
    if (!chosen.needle) {
      EXPECT_EQ(chosen.kernel_placed_vertices, 0);
    }
    on_flow += is_flow(r.method_used);
    on_flow_without_retry += is_flow(before.method_used);
    // A map that ended on a flow without the retry is the same map with it (the retry runs only when the mesh would
    // otherwise end on a one-shot method).
    if (is_flow(before.method_used) && before.ok()) {
      EXPECT_EQ(r.method_used, before.method_used);
      EXPECT_EQ(r.chosen_attempt, before.chosen_attempt);
      EXPECT_TRUE(r.sphere == before.sphere);
    }
  }
  std::printf("[needle spine] ended on a flow: %d of %zu (without the needle retry: %d)\n", on_flow, spines.size(),
              on_flow_without_retry);
  EXPECT_GE(on_flow, 13);                           // measured 13 (the target, >= 90 %)
  EXPECT_GE(on_flow, on_flow_without_retry + 2);     // measured 7 against 5
}

}  // namespace
}  // namespace wish::testing
