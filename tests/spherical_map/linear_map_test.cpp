// The linear fallback (FLASH steps 1–3, docs/design/spherical-map.md §8.2), the numerical-degeneracy criterion of the
// verification (§7), the local untangling, and the fallback chain's bookkeeping.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/linear_map.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/spherical_map/untangle.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

TEST(LinearMap, EllipsoidMapsBijectivelyWithBoundedDistortion) {
  const Mesh ellipsoid = testing::make_ellipsoid(1.0, 0.35, 0.35, 4);  // cigar, 2562 vertices
  const spherical::FlowResult flow = spherical::linear_map(spherical::MapContext(ellipsoid), {});
  ASSERT_EQ(flow.status, MapStatus::Ok) << flow.message;
  EXPECT_TRUE(flow.on_sphere);
  EXPECT_LT(((flow.vertices.rowwise().norm().array() - 1.0).abs()).maxCoeff(), 1e-12);

  SphericalMapOptions o;
  o.method = MapMethod::Linear;
  o.fallback = false;
  const SphericalMapResult r = compute_spherical_map(ellipsoid, o);
  EXPECT_TRUE(r.ok()) << to_string(r.failed_check);
  EXPECT_EQ(r.method_used, MapMethod::Linear);
  EXPECT_EQ(r.quality.flipped_faces, 0);
  EXPECT_EQ(r.quality.degree, 1);
  EXPECT_LT(r.quality.conformal_mean, 1.15);  // §9: 1.06–1.11
  EXPECT_LT(r.quality.mobius_centroid, 1e-8);
  EXPECT_EQ(map_method_from_name("linear"), MapMethod::Linear);
}

TEST(LinearMap, NegativeCotWeightsAreClampedSoTheMapStaysAnEmbedding) {
  // Shear an icosphere strongly: many obtuse triangles, negative cot weights.
  Mesh m = make_icosphere(3);
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i) {
    const Eigen::Vector3d p = m.vertices.row(i);
    m.vertices.row(i) = Eigen::RowVector3d(p.x() + 2.5 * p.y() * p.y() * p.z(), 0.3 * p.y(), p.z() + 0.8 * p.x());
  }
  const spherical::FlowResult flow = spherical::linear_map(spherical::MapContext(m), {});
  ASSERT_EQ(flow.status, MapStatus::Ok) << flow.message;
  EXPECT_TRUE(flow.clamped_weights) << flow.message;
  const MapQuality q = spherical::measure_map(m.vertices, m.faces, flow.vertices, {});
  EXPECT_EQ(q.flipped_faces, 0);
  EXPECT_EQ(q.degree, 1);
}

TEST(MapVerification, TinyIsNotDegenerateButNumericallyFlatIs) {
  // One small well-shaped triangle at the north pole (edges ~1e-7, area ~5e-15) and three points 1e-8 apart on
  // one great circle (height = the arc's sagitta ~5e-17, i.e. rounding noise): the first is a perfectly good
  // part of a map, the second's orientation cannot be decided in double precision.
  Eigen::MatrixX3d input(6, 3);
  input << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0;
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 3, 4, 5;
  Eigen::MatrixX3d u(6, 3);
  const double s = 1e-7, d = 1e-8;
  u.row(0) = Eigen::RowVector3d(0, 0, 1);
  u.row(1) = Eigen::RowVector3d(s, 0, 1).normalized();
  u.row(2) = Eigen::RowVector3d(0, s, 1).normalized();
  u.row(3) = Eigen::RowVector3d(1, 0, 0);
  u.row(4) = Eigen::RowVector3d(1, d, 0).normalized();
  u.row(5) = Eigen::RowVector3d(1, 2 * d, 0).normalized();
  const MapQuality q = spherical::measure_map(input, faces, u, {});
  EXPECT_EQ(q.degenerate_faces, 1);  // only the flat one
  EXPECT_LT(q.min_face_height, 1e-14);
  EXPECT_LT(q.min_face_area, 1e-14);
  EXPECT_GT(q.min_face_height, 0.0);
}

TEST(Untangle, RepairsAFewFoldedVerticesAndLeavesTheRestAlone) {
  const Mesh sphere = make_icosphere(3);
  Eigen::MatrixX3d u = sphere.vertices;
  const MapVerificationThresholds t;
  // Fold one vertex across its neighbours: move it past the opposite side of its 1-ring.
  const Eigen::Vector3d p = u.row(100), q = u.row(sphere.faces(0, 0));
  u.row(100) = (p + 3.0 * (q - p).normalized() * 0.2).normalized().transpose();
  const Eigen::MatrixX3d before = u;
  const long flips_before = spherical::measure_map(sphere.vertices, sphere.faces, u, t).flipped_faces;
  ASSERT_GT(flips_before, 0);
  const spherical::UntangleResult r = spherical::untangle_sphere_map(u, sphere.faces, t);
  EXPECT_EQ(r.bad_faces_after, 0);
  EXPECT_EQ(spherical::measure_map(sphere.vertices, sphere.faces, u, t).flipped_faces, 0);
  EXPECT_GT(r.moved_vertices, 0);
  EXPECT_LT(r.moved_vertices, sphere.vertex_count() / 4);
  EXPECT_LT(((u.rowwise().norm().array() - 1.0).abs()).maxCoeff(), 1e-12);
  (void)before;
}

TEST(FallbackChain, RecordsEveryAttemptAndReturnsTheChosenOne) {
  // An impossible distortion bound: every attempt fails verification, the chain runs to its end (the progressive
  // embedding, after the linear attempts), and the
  // least-bad attempt is returned with its status — never Ok.
  const Mesh ellipsoid = testing::make_ellipsoid(1.0, 0.7, 0.5, 3);
  SphericalMapOptions o;
  o.verification.max_conformal_p99 = 1.0;
  o.verification.strict_conformal_bound = true;  // the bound refuses only when asked to
  o.flow_budget_seconds = 0;
  o.chain_budget_seconds = 0;
  const SphericalMapResult r = compute_spherical_map(ellipsoid, o);
  EXPECT_FALSE(r.ok());
  ASSERT_GE(r.attempts.size(), 3u);
  EXPECT_EQ(r.attempts.front().method, MapMethod::Willmore);
  EXPECT_EQ(r.attempts.back().method, MapMethod::Progressive);
  EXPECT_EQ(r.attempts[r.attempts.size() - 2].method, MapMethod::Linear);
  ASSERT_GE(r.chosen_attempt, 0);
  ASSERT_LT(r.chosen_attempt, static_cast<int>(r.attempts.size()));
  const MapAttempt& chosen = r.attempts[static_cast<size_t>(r.chosen_attempt)];
  EXPECT_EQ(r.status, chosen.status);
  EXPECT_EQ(r.failed_check, MapCheck::ConformalDistortion);
  EXPECT_EQ(r.verdict, MapVerdict::Distorted);
  EXPECT_EQ(r.quality.conformal_p99, chosen.quality.conformal_p99);
  for (const MapAttempt& a : r.attempts) {
    EXPECT_NE(a.failed_check, MapCheck::None);
    EXPECT_GE(a.quality.conformal_p99, chosen.quality.conformal_p99);  // least bad: lowest K among bijective maps
  }
}

}  // namespace
}  // namespace wish
