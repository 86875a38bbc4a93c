// cMCF (cmcf.hpp): the flow's bookkeeping around its stops. A flow continued from an earlier run's last surface is
// the same flow run longer (the long attempt of the cMCF chain relies on it), and a flow that stops short of
// convergence hands back its roundest surface, not its last one (R is not monotone on elongated shapes).
#include <algorithm>

#include <gtest/gtest.h>

#include "core/geometry/roundness.hpp"
#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/cmcf.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

CmcfOptions never_stopping(int steps) {
  CmcfOptions o;
  o.max_steps = steps;
  o.roundness_tolerance = 0;   // never converged
  o.stall_patience = 1000;     // never stalled
  return o;
}

TEST(Cmcf, AContinuedFlowIsTheSameFlowRunLonger) {
  const Mesh cigar = testing::make_ellipsoid(3.0, 1.0, 1.0, 3);
  const spherical::FlowResult whole = spherical::cmcf_flow(spherical::MapContext(cigar), never_stopping(12));
  const spherical::FlowResult first = spherical::cmcf_flow(spherical::MapContext(cigar), never_stopping(5));
  ASSERT_TRUE(first.hit_step_cap);
  const Eigen::MatrixX3d& resume = first.last.size() > 0 ? first.last : first.vertices;
  const spherical::FlowResult rest =
      spherical::cmcf_flow(spherical::MapContext(cigar), never_stopping(7), {{}, {}, &resume});
  ASSERT_EQ(whole.steps.size(), 12u);
  ASSERT_EQ(rest.steps.size(), 7u);
  for (size_t k = 0; k < rest.steps.size(); ++k)
    EXPECT_NEAR(rest.steps[k].roundness, whole.steps[k + 5].roundness, 1e-9 * whole.steps[k + 5].roundness) << k;
  const Eigen::MatrixX3d& whole_last = whole.last.size() > 0 ? whole.last : whole.vertices;
  const Eigen::MatrixX3d& rest_last = rest.last.size() > 0 ? rest.last : rest.vertices;
  EXPECT_LT((whole_last - rest_last).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(Cmcf, AFlowStoppedShortHandsBackItsRoundestSurface) {
  // A flattened 6:1 ellipsoid: R falls for about ten steps, then climbs as the thin rim pinches (measured 0.37 at
  // step 3, 0.45 at step 20, 1.6 at step 40).
  const Mesh m = testing::make_ellipsoid(3.0, 0.5, 0.3, 4);
  const spherical::FlowResult flow = spherical::cmcf_flow(spherical::MapContext(m), never_stopping(40));
  ASSERT_EQ(flow.steps.size(), 40u);
  double roundest = flow.initial_roundness;
  for (const FlowStepRecord& s : flow.steps) roundest = std::min(roundest, s.roundness);
  ASSERT_LT(roundest, flow.steps.back().roundness);  // the case the test is about: the last surface is not the roundest
  EXPECT_EQ(flow.roundness, roundest);
  // (R from plain face areas here, from mollified ones in the flow: equal up to the mollification's ε.)
  EXPECT_NEAR(geometry::roundness(flow.vertices, m.faces), roundest, 1e-4 * roundest);
  ASSERT_EQ(flow.last.rows(), m.vertices.rows());  // the last surface is kept for a continued flow
  EXPECT_NEAR(geometry::roundness(flow.last, m.faces), flow.steps.back().roundness, 1e-4 * flow.steps.back().roundness);
}

}  // namespace
}  // namespace wish
