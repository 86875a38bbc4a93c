// The chain's needle retry (map_chain.cpp; docs/design/needle-flows.md): a Willmore flow with the needle operator
// (WillmoreOptions::needle_operator: H and mass from the intrinsic Delaunay operator, Poisson weights clamped to
// >= 0) and cMCF with a small time step, run after the flows and before the linear map, only while no Ok map is
// held; and the needle-aware choice between a flow's map and a one-shot map.
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/io/mesh_io.hpp"
#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/map_chain.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/spherical_map/willmore_flow.hpp"
#include "core/validation/mesh_report.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

bool is_flow(MapMethod m) { return m == MapMethod::Willmore || m == MapMethod::Cmcf; }

TEST(NeedleRetry, IsPlannedAfterTheFlowsAndBeforeTheLinearMap) {
  SphericalMapOptions o;  // the default chain: Willmore first
  const std::vector<MapAttemptPlan> plans = plan_attempts(o);
  std::vector<size_t> needle;
  for (size_t k = 0; k < plans.size(); ++k)
    if (plans[k].needle) needle.push_back(k);
  ASSERT_EQ(needle.size(), 2u);
  EXPECT_EQ(needle[1], needle[0] + 1);
  EXPECT_EQ(plans[needle[0]].method, MapMethod::Willmore);
  EXPECT_EQ(plans[needle[1]].method, MapMethod::Cmcf);
  for (size_t j = 0; j < needle[0]; ++j) EXPECT_FALSE(is_one_shot(plans[j].method)) << "attempt " << j;
  ASSERT_LT(needle[1] + 1, plans.size());
  EXPECT_EQ(plans[needle[1] + 1].method, MapMethod::Linear);
  o.needle_aware = false;
  for (const MapAttemptPlan& p : plan_attempts(o)) EXPECT_FALSE(p.needle);
  o.needle_aware = true;
  o.fallback = false;
  for (const MapAttemptPlan& p : plan_attempts(o)) EXPECT_FALSE(p.needle);
}

TEST(NeedleRetry, DoesNotRunWhenAnEarlierFlowMaps) {
  const SphericalMapResult r = compute_spherical_map(testing::make_ellipsoid(1.0, 0.8, 0.6, 3));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.method_used, MapMethod::Willmore);
  for (const MapAttempt& a : r.attempts) EXPECT_FALSE(a.needle);
}

TEST(NeedleRetry, RunsWhenNoFlowGivesAnOkMap) {
  // An impossible distortion bound: no attempt is Ok, so both attempts of the retry run (and are recorded as such).
  SphericalMapOptions o;
  o.verification.max_conformal_p99 = 1.0;
  o.verification.strict_conformal_bound = true;
  o.flow_budget_seconds = 0;
  o.chain_budget_seconds = 0;
  const SphericalMapResult r = compute_spherical_map(testing::make_ellipsoid(1.0, 0.7, 0.5, 3), o);
  EXPECT_FALSE(r.ok());
  int needle = 0;
  for (const MapAttempt& a : r.attempts) needle += a.needle;
  EXPECT_EQ(needle, 2);
}

TEST(NeedleOperator, ChangesNothingOnADelaunayMeshWithoutNegativeWeights) {
  // On a mesh whose cotan weights are all >= 0 and whose edges are all Delaunay, the intrinsic Delaunay operator is
  // the mollified one (no flip) and the clamp changes no weight: the two flows are the same computation.
  const Mesh ellipsoid = testing::make_ellipsoid(1.0, 0.9, 0.8, 3);
  SphericalMapOptions o;
  o.fallback = false;
  o.willmore.max_steps = 3;
  const SphericalMapResult plain = compute_spherical_map(ellipsoid, o);
  ASSERT_EQ(plain.attempts.size(), 1u);
  ASSERT_EQ(plain.attempts[0].operator_stats.negative_weights_before, 0);  // precondition of the identity
  o.willmore.needle_operator = true;
  const SphericalMapResult needle = compute_spherical_map(ellipsoid, o);
  ASSERT_EQ(needle.attempts.size(), 1u);
  ASSERT_EQ(needle.attempts[0].steps.size(), plain.attempts[0].steps.size());
  for (size_t k = 0; k < plain.attempts[0].steps.size(); ++k)
    EXPECT_NEAR(needle.attempts[0].steps[k].energy, plain.attempts[0].steps[k].energy,
                1e-9 * plain.attempts[0].steps[k].energy);
  EXPECT_LT((needle.sphere - plain.sphere).cwiseAbs().maxCoeff(), 1e-9);
}
