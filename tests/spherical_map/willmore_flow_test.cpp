// Flow properties and map assertions of docs/design/spherical-map.md §9.
#include <chrono>
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "core/common/errors.hpp"
#include "core/geometry/mean_curvature.hpp"
#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/cmcf.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/mobius.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/spherical_map/willmore_flow.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

constexpr double kFourPi = 4.0 * std::numbers::pi;

// A non-symmetric bumpy ellipsoid (no accidental symmetry, so the map is unique up to a rotation).
Mesh bumpy_shape(int level) {
  Mesh m = make_icosphere(level);
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i) {
    const Eigen::Vector3d p = m.vertices.row(i);
    const double r = 1.0 + 0.08 * std::sin(3 * p.x() + 1) * std::cos(2 * p.y()) + 0.05 * p.z() * p.x();
    m.vertices.row(i) = (r * p).cwiseProduct(Eigen::Vector3d(1.0, 0.8, 0.6)).transpose();
  }
  return m;
}

WillmoreOptions fixed_steps(int steps) {
  WillmoreOptions o;
  o.max_steps = steps;
  o.roundness_tolerance = 0;  // run exactly `steps` steps
  o.energy_tolerance = -1;
  o.roundness_stall = -1e300;  // no plateau stop either
  return o;
}

TEST(WillmoreFlow, SphereStaysSphere) {
  const Mesh sphere = make_icosphere(3);  // 642 vertices
  SphericalMapOptions o;
  o.willmore = fixed_steps(2);
  o.fallback = false;
  const SphericalMapResult r = compute_spherical_map(sphere, o);
  ASSERT_FALSE(r.attempts.empty());
  EXPECT_EQ(r.attempts[0].steps.size(), 2u);
  EXPECT_LT(r.quality.roundness, 1e-3);
  EXPECT_LT(r.quality.conformal_max, 1.01);
  EXPECT_EQ(r.quality.flipped_faces, 0);
  // Roundness tolerance 0 cannot be met: the flow stops at its step cap, which is reported (stop, message), not
  // hidden; its map verified (bijective, K 1.0), so like a flow stopped by the CPU budget it is an Ok answer.
  EXPECT_EQ(r.attempts[0].stop, FlowStop::StepCap);
  EXPECT_TRUE(r.attempts[0].hit_step_cap);
  EXPECT_NE(r.attempts[0].message.find("its map verified"), std::string::npos) << r.attempts[0].message;
  EXPECT_EQ(r.status, MapStatus::Ok);
  EXPECT_EQ(r.failed_check, MapCheck::None);
}

TEST(WillmoreFlow, AStepCappedFlowWhoseMapFailsIsNotOk) {
  // The other side of the rule: at the step cap a map that does not verify is a failure. A 10:1 ellipsoid after
  // one step is far from round; its radial projection is bijective, so ask for a strict distortion bound it
  // cannot meet.
  const Mesh cigar = testing::make_ellipsoid(5.0, 0.5, 0.5, 3);
  SphericalMapOptions o;
  o.willmore = fixed_steps(1);
  o.fallback = false;
  o.verification.strict_conformal_bound = true;
  o.verification.max_conformal_p99 = 1.01;
  const SphericalMapResult r = compute_spherical_map(cigar, o);
  EXPECT_EQ(r.attempts[0].stop, FlowStop::StepCap);
  EXPECT_NE(r.status, MapStatus::Ok);
  EXPECT_EQ(r.failed_check, MapCheck::ConformalDistortion);
}

TEST(WillmoreFlow, EllipsoidThresholdsEnergyMonotoneRoundnessFalls) {
  const Mesh ellipsoid = testing::make_ellipsoid(1.0, 0.7, 0.5, 4);  // 2562 vertices
  const spherical::FlowResult flow = spherical::willmore_flow(spherical::MapContext(ellipsoid), fixed_steps(6));
  ASSERT_EQ(flow.steps.size(), 6u);
  EXPECT_NEAR(flow.initial_energy / kFourPi, 1.205, 0.02);
  double energy = flow.initial_energy, roundness = flow.initial_roundness;
  for (const FlowStepRecord& s : flow.steps) {
    EXPECT_TRUE(s.accepted) << s.note;
    EXPECT_LE(s.energy, energy + 1e-3 * flow.initial_energy) << "step " << s.step;
    if (roundness > 1e-2) {
      EXPECT_LT(s.roundness, 0.5 * roundness) << "step " << s.step;
    }
    EXPECT_LT(s.eigen_residual, 1e-6);
    energy = s.energy;
    roundness = s.roundness;
  }
  EXPECT_LT(flow.roundness, 3e-3);
  EXPECT_LT(std::abs(flow.energy / kFourPi - 1.0), 1e-2);

  SphericalMapOptions o;
  o.willmore = fixed_steps(6);
  o.fallback = false;
  const SphericalMapResult r = compute_spherical_map(ellipsoid, o);
  EXPECT_EQ(r.quality.flipped_faces, 0);
  EXPECT_EQ(r.quality.degree, 1);
  EXPECT_LT(r.quality.conformal_mean, 1.05);
  EXPECT_LT(r.quality.conformal_max, 1.1);
}

TEST(WillmoreFlow, ReversedCurvatureChangeRaisesEnergy) {
  const Mesh ellipsoid = testing::make_ellipsoid(1.0, 0.7, 0.5, 3);
  WillmoreOptions o = fixed_steps(1);
  o.tau = -0.95;                          // ρ = +0.95 P(H): the wrong sign
  o.energy_increase_tolerance = 1e9;      // accept it, to see what it does
  const spherical::FlowResult flow = spherical::willmore_flow(spherical::MapContext(ellipsoid), o);
  ASSERT_EQ(flow.steps.size(), 1u);
  EXPECT_GT(flow.energy, 1.05 * flow.initial_energy);
  // ... and with the default tolerance such a step is rejected (τ halved until min_tau), and reported: no step
  // lowers the energy, which the flow treats as a stall (a stop judged by verification), not as progress.
  o.energy_increase_tolerance = 1e-3;
  o.min_tau = 0.3;
  const spherical::FlowResult rejected = spherical::willmore_flow(spherical::MapContext(ellipsoid), o);
  EXPECT_EQ(rejected.status, MapStatus::Ok);
  EXPECT_EQ(rejected.stop, FlowStop::EnergyStall) << rejected.message;
  ASSERT_GE(rejected.steps.size(), 2u);
  for (const FlowStepRecord& s : rejected.steps) EXPECT_FALSE(s.accepted);
  EXPECT_EQ(rejected.energy, rejected.initial_energy);  // the surface was not moved
}

TEST(WillmoreFlow, DefaultMapIsOkBijectiveAndBalanced) {
  const Mesh shape = bumpy_shape(4);
  const SphericalMapResult r = compute_spherical_map(shape);
  ASSERT_TRUE(r.ok()) << to_string(r.failed_check) << " " << r.attempts.back().message;
  EXPECT_EQ(r.method_used, MapMethod::Willmore);
  EXPECT_EQ(r.attempts.size(), 1u);
  EXPECT_EQ(r.quality.flipped_faces, 0);
  EXPECT_EQ(r.quality.degenerate_faces, 0);
  EXPECT_EQ(r.quality.degree, 1);
  EXPECT_LT(r.quality.mobius_centroid, 1e-8);
  EXPECT_LT((r.sphere.rowwise().norm().array() - 1.0).abs().maxCoeff(), 1e-12);
  EXPECT_LT(r.quality.roundness, 2e-3);
  EXPECT_LT(r.quality.conformal_mean, 1.05);
  EXPECT_GT(r.quality.area_distortion, 1.0);
}

TEST(WillmoreFlow, SolverVariantsGiveTheSameMap) {
  const Mesh shape = bumpy_shape(3);
  SphericalMapOptions o;
  const SphericalMapResult a = compute_spherical_map(shape, o);
  o.solver = LinearSolverKind::EigenSimplicial;
  const SphericalMapResult b = compute_spherical_map(shape, o);
  o.solver = LinearSolverKind::Cholmod;
  o.willmore.complex_dirac = false;
  const SphericalMapResult c = compute_spherical_map(shape, o);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  // λ is unique up to a constant right factor, i.e. maps agree up to a rotation: compare Gram matrices.
  const Eigen::MatrixXd ga = a.sphere * a.sphere.transpose();
  EXPECT_LT((ga - b.sphere * b.sphere.transpose()).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((ga - c.sphere * c.sphere.transpose()).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(WillmoreFlow, InvariantUnderRigidMotionAndScale) {
  const Mesh shape = bumpy_shape(3);
  Mesh moved = shape;
  const Eigen::Matrix3d rot = testing::random_rotation(testing::test_seed());
  moved.vertices = ((3.7 * shape.vertices * rot.transpose()).rowwise() + Eigen::RowVector3d(5, -2, 1)).eval();
  const SphericalMapResult a = compute_spherical_map(shape);
  const SphericalMapResult b = compute_spherical_map(moved);
  ASSERT_TRUE(a.ok() && b.ok());
  const Eigen::MatrixXd diff = a.sphere * a.sphere.transpose() - b.sphere * b.sphere.transpose();
  EXPECT_LT(diff.cwiseAbs().maxCoeff(), 1e-6);
}

TEST(WillmoreFlow, FilteredFlowKeepsNoisyInputConformal) {
  Mesh noisy = make_icosphere(4);
  std::mt19937 rng(testing::test_seed());
  std::normal_distribution<double> n(0.0, 0.02);
  for (Eigen::Index i = 0; i < noisy.vertex_count(); ++i) noisy.vertices.row(i) *= 1.0 + n(rng);
  SphericalMapOptions o;
  o.willmore.filtered = true;
  o.willmore.max_steps = 10;
  o.fallback = false;
  const SphericalMapResult r = compute_spherical_map(noisy, o);
  EXPECT_EQ(r.quality.flipped_faces, 0);
  EXPECT_LT(r.quality.conformal_mean, 1.15);  // unfiltered drifts far higher (docs/design/spherical-map.md §9)
  EXPECT_TRUE(r.attempts[0].filtered);
}

TEST(Cmcf, BaselineRoundsTheEllipsoidWithoutFlips) {
  const Mesh ellipsoid = testing::make_ellipsoid(1.0, 0.7, 0.5, 4);
  CmcfOptions c;
  c.max_steps = 20;
  c.roundness_tolerance = 0;
  c.min_steps_before_stall = 1000;  // run exactly 20 steps
  const spherical::FlowResult flow = spherical::cmcf_flow(spherical::MapContext(ellipsoid), c);
  EXPECT_EQ(flow.steps.size(), 20u);
  EXPECT_LT(flow.roundness, 3e-2);
  SphericalMapOptions o;
  o.method = MapMethod::Cmcf;
  o.fallback = false;
  const SphericalMapResult r = compute_spherical_map(ellipsoid, o);
  EXPECT_EQ(r.quality.flipped_faces, 0);
  EXPECT_EQ(r.method_used, MapMethod::Cmcf);
  EXPECT_LT(r.quality.conformal_mean, 1.1);
}

TEST(Mobius, BalancesAnOffCentreMapWithoutFlips) {
  const Mesh sphere = make_icosphere(3);
  Eigen::MatrixX3d u = sphere.vertices;
  // Push points toward +z with a Möbius map, then balance back.
  const Eigen::Vector3d a(0.1, -0.2, 0.6);
  for (Eigen::Index i = 0; i < u.rows(); ++i) {
    const Eigen::Vector3d p = u.row(i), d = p - a;
    u.row(i) = ((1 - a.squaredNorm()) * d / d.squaredNorm() - a).normalized().transpose();
  }
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(u.rows());
  EXPECT_GT((u.transpose() * w).norm() / u.rows(), 0.1);
  const spherical::MobiusResult r = spherical::mobius_balance(u, w);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.centroid, 1e-8);
  const MapQuality q = spherical::measure_map(sphere.vertices, sphere.faces, u, {});
  EXPECT_EQ(q.flipped_faces, 0);
  EXPECT_EQ(q.degree, 1);
}

TEST(MapVerification, DetectsReflectionAndCollapse) {
  const Mesh sphere = make_icosphere(2);
  Eigen::MatrixX3d mirrored = sphere.vertices;
  mirrored.col(0) *= -1;
  const MapQuality q = spherical::measure_map(sphere.vertices, sphere.faces, mirrored, {});
  EXPECT_EQ(q.flipped_faces, sphere.face_count());
  EXPECT_EQ(q.degree, -1);
  EXPECT_EQ(spherical::failed_map_check(q, {}), MapCheck::FlippedFaces);
  const MapQuality id = spherical::measure_map(sphere.vertices, sphere.faces, sphere.vertices, {});
  EXPECT_EQ(id.flipped_faces, 0);
  EXPECT_NEAR(id.conformal_max, 1.0, 1e-9);
  EXPECT_NEAR(id.area_distortion, 1.0, 1e-9);
  EXPECT_EQ(spherical::failed_map_check(id, {}), MapCheck::None);
  Eigen::MatrixX3d collapsed = sphere.vertices;
  collapsed.row(sphere.faces(0, 0)) = collapsed.row(sphere.faces(0, 1));
  EXPECT_GT(spherical::measure_map(sphere.vertices, sphere.faces, collapsed, {}).degenerate_faces, 0);
}

TEST(SphericalMap, ContractErrors) {
  EXPECT_EQ(map_method_from_name("cmcf"), MapMethod::Cmcf);
  EXPECT_THROW(map_method_from_name("lscm"), InvalidInputError);
  Mesh open = make_icosphere(2);
  open.faces.conservativeResize(open.face_count() - 1, 3);
  // A mesh that validation would refuse is refused by the map too, with validation's code and category (422).
  auto refusal = [](const Mesh& mesh) -> std::pair<std::string, ErrorCategory> {
    try {
      (void)compute_spherical_map(mesh);
    } catch (const WishError& e) {
      return {e.code(), e.category()};
    }
    return {"", ErrorCategory::Internal};
  };
  EXPECT_EQ(refusal(open).second, ErrorCategory::Unmappable);  // an open mesh fails the Euler characteristic first
  Mesh inward = make_icosphere(2);
  inward.faces.col(1).swap(inward.faces.col(2));
  EXPECT_EQ(refusal(inward).second, ErrorCategory::Unmappable);
  const Mesh sphere = testing::make_ellipsoid(1, 0.7, 0.5, 3);
  EXPECT_THROW(compute_spherical_map(sphere, {}, Deadline::after(std::chrono::seconds(0))), TimeoutError);
}

}  // namespace
}  // namespace wish
