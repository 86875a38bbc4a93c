// Which map the fallback chain returns (compute_spherical_map): by default the least distorted Ok map of any
// method; with prefer_method (a model that refuses other methods' maps) an Ok map of the requested method, and the
// chain then runs only that method's later attempts.
#include <gtest/gtest.h>

#include "core/spherical_map/spherical_map.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

// Willmore stopped at a 1-step cap of a small step on a 4:1 cigar: a bijective map, far from conformal, Ok and
// provisional (the chain goes on: one more step, then cMCF run to convergence, which is less distorted).
SphericalMapOptions short_willmore() {
  SphericalMapOptions o;
  o.method = MapMethod::Willmore;
  o.willmore.max_steps = 1;
  o.willmore.roundness_tolerance = 0;
  o.willmore.energy_tolerance = -1;
  o.willmore.roundness_stall = -1e300;
  o.willmore.tau = 0.05;  // a small step: the cigar stays a cigar
  o.willmore.min_tau = 0.01;
  o.flow_budget_seconds = 0;  // no CPU budget: the same chain under any load
  o.chain_budget_seconds = 0;
  return o;
}

TEST(ChainChoice, TheLeastDistortedOkMapWinsByDefault) {
  const Mesh cigar = testing::make_ellipsoid(2.0, 0.5, 0.5, 3);
  const SphericalMapResult r = compute_spherical_map(cigar, short_willmore());
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.attempts.front().method, MapMethod::Willmore);
  EXPECT_EQ(r.attempts.front().status, MapStatus::Ok);  // verified at its step cap
  EXPECT_TRUE(r.attempts.front().hit_step_cap);
  EXPECT_NE(r.method_used, MapMethod::Willmore);  // another method's map was less distorted
  for (const MapAttempt& a : r.attempts) {
    if (a.status == MapStatus::Ok) {
      EXPECT_GE(a.quality.conformal_p99, r.quality.conformal_p99);
    }
  }
}

TEST(ChainChoice, PreferMethodKeepsTheRequestedMethodsMapAndSkipsTheOthers) {
  const Mesh cigar = testing::make_ellipsoid(2.0, 0.5, 0.5, 3);
  SphericalMapOptions o = short_willmore();
  o.prefer_method = true;
  const SphericalMapResult r = compute_spherical_map(cigar, o);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.method_used, MapMethod::Willmore);
  EXPECT_GE(r.attempts.size(), 2u);  // the same flow continued ("more steps") still ran
  for (const MapAttempt& a : r.attempts) EXPECT_EQ(a.method, MapMethod::Willmore);
}

}  // namespace
}  // namespace wish
