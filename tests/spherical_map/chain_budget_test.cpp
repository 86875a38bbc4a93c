// The time bound of the map chain (issue 11; compute_spherical_map, SphericalMapOptions::flow_budget_seconds):
// whatever the budget, the chain returns a verified bijective map, and every stop the budget causes is reported
// (the stopped flow's FlowStop::TimeBudget, the attempts it skipped in skipped_for_budget). Asserted on the reported
// stops and attempt records only, never on seconds (speed is measured in bench/map_collection_bench).
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/validation/mesh_report.hpp"
#include "tests/spherical_map/coil_mesh.hpp"

namespace wish {
namespace {

// A tube of radius 0.12 along 1.5 turns of a helix (as in real_mesh_test): far from star-shaped, so the radial
// projection of the unflowed surface folds over and only a flow or the linear method maps it bijectively.
using testing::make_coil;

void expect_bijective(const SphericalMapResult& r) {
  EXPECT_TRUE(r.ok()) << to_string(r.failed_check) << ": " << r.attempts.back().message;
  EXPECT_EQ(r.quality.flipped_faces, 0);
  EXPECT_EQ(r.quality.degenerate_faces, 0);
  EXPECT_EQ(r.quality.degree, 1);
  EXPECT_EQ(r.quality.non_finite_vertices, 0);
  EXPECT_NE(r.verdict, MapVerdict::Failed);
}

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
  const SphericalMapResult r = compute_spherical_map(make_coil(), o);
  expect_bijective(r);
  EXPECT_TRUE(r.skipped_for_budget.empty());
  for (const MapAttempt& a : r.attempts) {
    EXPECT_NE(a.stop, FlowStop::TimeBudget);
    EXPECT_NE(a.failed_check, MapCheck::TimeBudget);
  }
}

}  // namespace
}  // namespace wish
