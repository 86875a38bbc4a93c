// The area-aware correction after the conformal map (density_equalizing.hpp): it keeps the map bijective, it
// reduces the area distortion where the conformal map compresses (an elongated ellipsoid, a dumbbell with a thin
// neck), it is the identity on a map that is already equiareal (a round sphere onto itself), and the SH invariants
// of the corrected map stay rotation-invariant.
#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/mesh/icosphere.hpp"
#include "core/sh/sh_fit.hpp"
#include "core/spherical_map/density_equalizing.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "tests/spherical_map/map_checks.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

using testing::deformed_icosphere;
using testing::expect_bijective;

Mesh dumbbell() {  // the neck of real_mesh_test (radius 0.15 of the bulbs' 1)
  return deformed_icosphere(4, [](const Eigen::Vector3d& p) {
    const double s = 0.15 + 0.85 * std::pow(std::abs(p.x()), 0.7);
    return Eigen::Vector3d(2.5 * p.x(), s * p.y(), s * p.z());
  });
}

SphericalMapOptions corrected_cmcf() {
  SphericalMapOptions o;
  o.method = MapMethod::Cmcf;
  // The conformal maps these figures were measured on: cMCF stopping at its first R plateau. On the rounder map of
  // the 4:1:1 ellipsoid that patience 20 reaches, the correction lowers |log r| p99 6.06 -> 4.98 but raises its max
  // 6.21 -> 7.28 (K p99 1.2 -> 206): one more reason it stays off by default (docs/accuracy.md, run C).
  o.cmcf.stall_patience = 1;
  o.flow_budget_seconds = 0;  // no CPU budget: the same map under any load
  o.chain_budget_seconds = 0;
  o.area_correction.method = AreaCorrection::DensityEqualizing;
  o.area_correction.budget_seconds = 0;
  return o;
}

void print(const char* what, const AreaCorrectionReport& c) {
  std::printf("[dem] %-22s stop %-13s iterations %3d rejected %2d |log r| p99 %.3f -> %.3f max %.3f -> %.3f "
              "K p99 %.2f -> %.2f  %.3f CPU s\n",
              what, to_string(c.stop), c.iterations, c.rejected_steps, c.before.log_ratio_p99, c.after.log_ratio_p99,
              c.before.log_ratio_max, c.after.log_ratio_max, c.conformal_p99_before, c.conformal_p99_after, c.seconds);
}

TEST(DensityEqualizing, IsTheIdentityOnARoundSphere) {
  // The sphere onto itself is equiareal (every area share equals its input share): nothing may move.
  const Mesh sphere = make_icosphere(3);
  Eigen::MatrixX3d u = sphere.vertices.rowwise().normalized();
  const Eigen::MatrixX3d before = u;
  AreaCorrectionOptions o;
  o.budget_seconds = 0;
  o.tolerance = 0;  // no early "converged": the flow itself must stand still
  const AreaCorrectionReport r = spherical::equalize_sphere_density(u, 3.0 * sphere.vertices, sphere.faces, o, 1e-14);
  EXPECT_LT(r.before.log_ratio_max, 1e-12);
  EXPECT_LT((u - before).cwiseAbs().maxCoeff(), 1e-12);
  // And through the whole chain: the cMCF map of a round sphere is (up to rotation) the identity, already equiareal.
  const SphericalMapResult m = compute_spherical_map(sphere, corrected_cmcf());
  expect_bijective(m);
  EXPECT_EQ(m.area_correction.stop, AreaCorrectionStop::Converged);
  EXPECT_EQ(m.area_correction.iterations, 0);
}

TEST(DensityEqualizing, ReducesAreaDistortionAndKeepsTheMapBijective) {
  struct Case {
    const char* name;
    Mesh mesh;
  };
  const Case cases[] = {{"ellipsoid 4:1:1", testing::make_ellipsoid(2.0, 0.5, 0.5, 4)}, {"dumbbell (neck 0.15)", dumbbell()}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    SphericalMapOptions plain = corrected_cmcf();
    plain.area_correction.method = AreaCorrection::None;
    const SphericalMapResult conformal = compute_spherical_map(c.mesh, plain);
    const SphericalMapResult corrected = compute_spherical_map(c.mesh, corrected_cmcf());
    expect_bijective(conformal);
    expect_bijective(corrected);
    const AreaCorrectionReport& r = corrected.area_correction;
    print(c.name, r);
    EXPECT_EQ(conformal.area_correction.stop, AreaCorrectionStop::NotRun);
    EXPECT_NE(r.stop, AreaCorrectionStop::Reverted);
    EXPECT_GT(r.iterations, 0);
    // The report's "before" is the conformal map, its "after" the returned one, measured independently here.
    const AreaDistortionFigures before = spherical::area_distortion_figures(c.mesh.vertices, c.mesh.faces, conformal.sphere);
    const AreaDistortionFigures after = spherical::area_distortion_figures(c.mesh.vertices, c.mesh.faces, corrected.sphere);
    EXPECT_NEAR(r.before.log_ratio_p99, before.log_ratio_p99, 1e-9);
    EXPECT_NEAR(r.after.log_ratio_p99, after.log_ratio_p99, 1e-9);
    // More equiareal: the area energy, the p99 and the max of |log area ratio| are lower. (Only modestly, as
    // measured: ellipsoid p99 6.30 -> 5.50, dumbbell 19.72 -> 19.67 — the step control stops early; see
    // density_equalizing.hpp and docs/accuracy.md. A stronger bound would fail today.)
    EXPECT_LT(r.after.energy, r.before.energy);
    EXPECT_LT(after.log_ratio_p99, before.log_ratio_p99);
    EXPECT_LT(after.log_ratio_max, before.log_ratio_max);
    // The price is conformality: K goes up (so the correction really moved the map).
    EXPECT_GT(corrected.quality.conformal_p99, conformal.quality.conformal_p99);
  }
}

TEST(DensityEqualizing, StepControlStopsRatherThanFlip) {
  // Huge steps and no cap: every step must be halved until it keeps all faces unflipped (or the flow stops).
  const Mesh m = dumbbell();
  SphericalMapOptions plain = corrected_cmcf();
  plain.area_correction.method = AreaCorrection::None;
  SphericalMapResult conformal = compute_spherical_map(m, plain);
  ASSERT_TRUE(conformal.ok());
  AreaCorrectionOptions o;
  o.budget_seconds = 0;
  o.step = 50;
  o.max_step = 1e6;
  o.max_iterations = 20;
  Eigen::MatrixX3d u = conformal.sphere;
  const AreaCorrectionReport r = spherical::equalize_sphere_density(u, m.vertices, m.faces, o, 1e-14);
  print("dumbbell, huge steps", r);
  EXPECT_GT(r.rejected_steps, 0);
  const MapQuality q = spherical::measure_map(m.vertices, m.faces, u, {});
  EXPECT_EQ(q.flipped_faces, 0);
  EXPECT_EQ(q.degenerate_faces, 0);
  EXPECT_EQ(q.degree, 1);
  EXPECT_LE(r.after.energy, r.before.energy);
}

TEST(DensityEqualizing, InvariantsStayRotationInvariant) {
  const Mesh m = testing::make_ellipsoid(1.6, 0.8, 0.5, 3);
  Mesh rotated = m;
  const Eigen::Matrix3d rot = testing::random_rotation(testing::test_seed(7));
  rotated.vertices = (m.vertices * rot.transpose()).eval();
  const SphericalMapResult a = compute_spherical_map(m, corrected_cmcf());
  const SphericalMapResult b = compute_spherical_map(rotated, corrected_cmcf());
  expect_bijective(a);
  expect_bijective(b);
  ASSERT_GT(a.area_correction.iterations, 0);
  ShFitOptions fit;
  fit.lmax = 8;
  const Eigen::VectorXd xa = fit_spherical_harmonics(m, a.sphere, fit).invariants;
  const Eigen::VectorXd xb = fit_spherical_harmonics(rotated, b.sphere, fit).invariants;
  for (Eigen::Index l = 0; l < xa.size(); ++l)
    EXPECT_NEAR(xb[l], xa[l], 1e-6 * xa.cwiseAbs().maxCoeff() + 1e-4 * std::abs(xa[l])) << "l = " << l;
}

TEST(DensityEqualizing, NamesRoundTrip) {
  for (AreaCorrection c : {AreaCorrection::None, AreaCorrection::DensityEqualizing})
    EXPECT_EQ(area_correction_from_name(to_string(c)), c);
  EXPECT_EQ(area_correction_from_name("dem"), AreaCorrection::DensityEqualizing);
  EXPECT_THROW((void)area_correction_from_name("authalic"), InvalidInputError);
}

}  // namespace
}  // namespace wish
