// The time bound of the map chain (issue 11; compute_spherical_map, SphericalMapOptions::flow_budget_seconds and
// chain_budget_seconds): whatever the budget, the chain returns a verified bijective map or a failure (never a map
// with flips as Ok), and every stop the budget causes is reported (the stopped flow's FlowStop::TimeBudget, a repair
// stopped by the chain budget in repair_budget_stopped, the attempts it skipped in skipped_for_budget). Asserted on
// the reported stops, attempt records and the map itself only, never on seconds (speed is measured in
// bench/map_collection_bench).
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/common/cpu_budget.hpp"
#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/chart_untangle.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/spherical_map/untangle.hpp"
#include "core/validation/mesh_report.hpp"
#include "tests/spherical_map/coil_mesh.hpp"
#include "tests/spherical_map/map_checks.hpp"

namespace wish {
namespace {

// A tube of radius 0.12 along 1.5 turns of a helix (as in real_mesh_test): far from star-shaped, so the radial
// projection of the unflowed surface folds over and only a flow or the linear method maps it bijectively.
using testing::make_coil;

using testing::expect_bijective;

TEST(ChainBudget, ASpentBudgetStillEndsOnAVerifiedBijectiveMapAndReportsEveryStop) {
  const Mesh coil = make_coil();
  ASSERT_TRUE(prepare_for_mapping(coil).mappable());
  SphericalMapOptions o;
  o.flow_budget_seconds = 1e-9;  // spent before the first flow step: the flow keeps its (unflowed) start surface
  const SphericalMapResult r = compute_spherical_map(coil, o);
  expect_bijective(r);
  ASSERT_FALSE(r.attempts.empty());
  const MapAttempt& first = r.attempts.front();
  EXPECT_EQ(first.method, MapMethod::Willmore);
  EXPECT_EQ(first.stop, FlowStop::TimeBudget);
  EXPECT_TRUE(first.steps.empty());  // the budget is checked before every step try
  // No flow starts after the budget: cMCF (planned after Willmore) is reported as skipped, never silently dropped.
  for (size_t k = 1; k < r.attempts.size(); ++k) EXPECT_EQ(r.attempts[k].method, MapMethod::Linear) << "attempt " << k;
  bool cmcf_skipped = false;
  for (const MapAttemptPlan& p : r.skipped_for_budget) {
    EXPECT_NE(p.method, MapMethod::Linear);  // without an Ok map the linear attempts always run
    cmcf_skipped = cmcf_skipped || p.method == MapMethod::Cmcf;
  }
  EXPECT_TRUE(cmcf_skipped);
  // The answer: the linear method when the unflowed projection did not verify (a fold the repair could not undo),
  // else the repaired projection itself — an Ok map held when the budget is spent ends the chain.
  if (first.status == MapStatus::Ok) {
    EXPECT_EQ(r.attempts.size(), 1u);
    EXPECT_EQ(r.method_used, MapMethod::Willmore);
  } else {
    EXPECT_EQ(r.method_used, MapMethod::Linear);
    EXPECT_EQ(r.attempts.back().method, MapMethod::Linear);
  }
  EXPECT_GT(r.cpu_seconds, 0);
  for (const MapAttempt& a : r.attempts) EXPECT_GE(a.cpu_seconds, 0);
}

TEST(ChainBudget, WithoutABudgetNothingStopsForTime) {
  // Same coil, budget off (0): the same chain reports no time_budget stop and skips nothing for time.
  SphericalMapOptions o;
  o.flow_budget_seconds = 0;
  o.chain_budget_seconds = 0;
  const SphericalMapResult r = compute_spherical_map(make_coil(), o);
  expect_bijective(r);
  EXPECT_TRUE(r.skipped_for_budget.empty());
  for (const MapAttempt& a : r.attempts) {
    EXPECT_NE(a.stop, FlowStop::TimeBudget);
    EXPECT_NE(a.failed_check, MapCheck::TimeBudget);
  }
}

// A sphere map with a few flipped faces: the icosphere's own vertices (a bijective map) with one vertex folded
// across its 1-ring (as in linear_map_test's Untangle test).
struct FoldedMap {
  Mesh mesh = make_icosphere(3);
  Eigen::MatrixX3d sphere;
  FoldedMap() : sphere(mesh.vertices) {
    const Eigen::Vector3d p = sphere.row(100), q = sphere.row(mesh.faces(0, 0));
    sphere.row(100) = (p + 3.0 * (q - p).normalized() * 0.2).normalized().transpose();
  }
  long bad_faces() const {
    long n = 0;
    for (Eigen::Index f = 0; f < mesh.face_count(); ++f)
      n += spherical::is_bad_sphere_face(sphere, mesh.faces, f, MapVerificationThresholds{}.degenerate_height);
    return n;
  }
};

CpuBudget spent_budget() { return CpuBudget::for_this_thread(std::chrono::duration<double>(0)); }

// Either repair (`repair(sphere, budget)` → a result with budget_stopped, moved_vertices, bad_faces_after) on the
// folded map: with a spent budget it stops before its first move, reports the stop and the flips it left, and
// leaves the map as it was; metamorphic check: the same map with an unlimited budget is repaired (so the stop is
// the budget's doing).
template <class Repair>
void expect_repair_respects_its_budget(Repair repair) {
  FoldedMap folded;
  const long bad = folded.bad_faces();
  ASSERT_GT(bad, 0);
  const Eigen::MatrixX3d before = folded.sphere;
  const auto stopped = repair(folded.sphere, spent_budget());
  EXPECT_TRUE(stopped.budget_stopped);
  EXPECT_EQ(stopped.moved_vertices, 0);
  EXPECT_EQ(stopped.bad_faces_after, bad);  // the flips are reported, not hidden
  EXPECT_EQ(folded.sphere, before);
  const auto free = repair(folded.sphere, CpuBudget{});
  EXPECT_FALSE(free.budget_stopped);
  EXPECT_EQ(free.bad_faces_after, 0);
  EXPECT_EQ(folded.bad_faces(), 0);
}

TEST(RepairBudget, ChartUntanglingStopsOnASpentBudgetAndLeavesTheMapAsItWas) {
  const FoldedMap input;
  expect_repair_respects_its_budget([&](Eigen::MatrixX3d& sphere, const CpuBudget& budget) {
    return spherical::untangle_in_charts(sphere, input.mesh.vertices, input.mesh.faces, {}, {}, budget);
  });
}

TEST(RepairBudget, TutteRelaxationStopsOnASpentBudgetAndLeavesTheMapAsItWas) {
  const FoldedMap input;
  expect_repair_respects_its_budget([&](Eigen::MatrixX3d& sphere, const CpuBudget& budget) {
    return spherical::untangle_sphere_map(sphere, input.mesh.faces, {}, {}, budget);
  });
}

TEST(ChainBudget, ASpentChainBudgetStopsTheRepairAndNeverAcceptsAMapWithFlips) {
  // Input: the folded icosphere itself (a surface with one vertex pushed across its 1-ring). With the flow budget
  // spent before the first step, the first attempt's map is the radial projection, folded like the input: it needs
  // the repair. Paired runs that differ only in the chain budget:
  //  * no chain budget: the repair runs and the first attempt is Ok (so the repair can do it);
  //  * chain budget spent: the repair stops before its first move, the attempt reports it and fails on its flips,
  //    the fallback flows are skipped, the linear attempts still run; an Ok answer, if any, has no flips.
  FoldedMap folded;
  Mesh mesh = folded.mesh;
  mesh.vertices = folded.sphere;
  SphericalMapOptions o;
  o.flow_budget_seconds = 1e-9;
  o.chain_budget_seconds = 0;
  const SphericalMapResult repaired = compute_spherical_map(mesh, o);
  ASSERT_FALSE(repaired.attempts.empty());
  const MapAttempt& free = repaired.attempts.front();
  ASSERT_EQ(free.stop, FlowStop::TimeBudget);
  EXPECT_EQ(free.status, MapStatus::Ok) << free.message;
  EXPECT_GT(free.quality.repaired_vertices, 0);
  EXPECT_FALSE(free.repair_budget_stopped);

  o.chain_budget_seconds = 1e-9;
  const SphericalMapResult r = compute_spherical_map(mesh, o);
  ASSERT_FALSE(r.attempts.empty());
  const MapAttempt& first = r.attempts.front();
  EXPECT_EQ(first.method, MapMethod::Willmore);
  EXPECT_TRUE(first.repair_budget_stopped);
  EXPECT_EQ(first.status, MapStatus::VerificationFailed);
  EXPECT_EQ(first.quality.repaired_vertices, 0);
  EXPECT_GT(first.quality.flipped_faces + first.quality.degenerate_faces, 0);
  EXPECT_NE(first.message.find("repair stopped"), std::string::npos) << first.message;
  bool linear_ran = false;
  for (const MapAttempt& a : r.attempts) {
    linear_ran = linear_ran || a.method == MapMethod::Linear;
    if (a.repair_budget_stopped) {
      EXPECT_NE(a.status, MapStatus::Ok);
    }
  }
  EXPECT_TRUE(linear_ran);
  EXPECT_FALSE(r.skipped_for_budget.empty());  // the fallback flows did not start
  for (const MapAttemptPlan& p : r.skipped_for_budget) EXPECT_NE(p.method, MapMethod::Linear);
  if (r.ok()) {
    EXPECT_EQ(r.quality.flipped_faces, 0);
    EXPECT_EQ(r.quality.degenerate_faces, 0);
  } else {
    EXPECT_EQ(r.verdict, MapVerdict::Failed);
  }
}

}  // namespace
}  // namespace wish
