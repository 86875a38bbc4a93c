// The canonical map (canonical_map.hpp, issue 37): the distortion energy's derivatives are those of its value
// (finite differences), its projected Hessian is positive semidefinite, a round sphere is already canonical, every
// relaxation step keeps the map bijective, and — the point of the definition — the canonical map and its ξ do not
// depend on which map the relaxation started from (a conformal flow's or the linear map's), nor on a rotation.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include <filesystem>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/io/mesh_io.hpp"
#include "core/mesh/icosphere.hpp"
#include "core/sh/sh_fit.hpp"
#include "core/spherical_map/canonical_map.hpp"
#include "core/spherical_map/distortion_energy.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "tests/spherical_map/map_checks.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

using spherical::DistortionEnergy;
using spherical::DistortionEnergyKind;
using testing::expect_bijective;

Eigen::Matrix2d random_positive_jacobian(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (;;) {
    Eigen::Matrix2d F;
    F << 1.0 + u(rng), u(rng), u(rng), 1.0 + u(rng);
    if (F.determinant() > 0.2) return F;
  }
}

TEST(DistortionEnergy, GradientAndHessianMatchFiniteDifferences) {
  std::mt19937 rng(testing::test_seed(11));
  for (const DistortionEnergyKind kind : {DistortionEnergyKind::SymmetricDirichlet, DistortionEnergyKind::ConformalArea}) {
    SCOPED_TRACE(spherical::to_string(kind));
    DistortionEnergy e;
    e.kind = kind;
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::Matrix2d F = random_positive_jacobian(rng);
      Eigen::Matrix2d grad;
      e.gradient(F, grad);
      const double h = 1e-6;
      for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 2; ++c) {
          Eigen::Matrix2d plus = F, minus = F;
          plus(r, c) += h;
          minus(r, c) -= h;
          EXPECT_NEAR(grad(r, c), (e.value(plus) - e.value(minus)) / (2 * h), 1e-6 * (1 + std::abs(grad(r, c))));
        }
      // The projected Hessian is symmetric positive semidefinite.
      const Eigen::Matrix4d H = e.projected_hessian(F);
      EXPECT_LT((H - H.transpose()).cwiseAbs().maxCoeff(), 1e-10);
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(H).eigenvalues().minCoeff(), -1e-9);
    }
    // The minimum is reached at rotations, and a flipped F is infinitely far.
    EXPECT_NEAR(e.value(Eigen::Rotation2Dd(0.7).toRotationMatrix()), e.minimum(), 1e-12);
    Eigen::Matrix2d flipped = Eigen::Matrix2d::Identity();
    flipped(1, 1) = -1;
    EXPECT_TRUE(std::isinf(e.value(flipped)));
  }
}

TEST(CanonicalMap, ARoundSphereIsAlreadyCanonical) {
  // The unit icosphere onto itself: each chord face is its own reference up to the 4π area scale, so the energy is
  // within that scale of the minimum and the relaxation converges without moving anything far.
  const Mesh sphere = make_icosphere(3);
  Eigen::MatrixX3d u = sphere.vertices.rowwise().normalized();
  const Eigen::MatrixX3d start = u;
  CanonicalMapOptions o;
  o.method = CanonicalMap::Isometric;
  o.budget_seconds = 0;
  const CanonicalMapReport r = spherical::relax_to_canonical_map(u, 2.0 * sphere.vertices, sphere.faces, o, 1e-14);
  EXPECT_EQ(r.stop, CanonicalMapStop::Converged);
  EXPECT_LT(r.energy_start - o.energy.minimum(), 0.01);
  EXPECT_LE(r.energy, r.energy_start);
  EXPECT_LT((u - start).rowwise().norm().maxCoeff(), 0.05);
}

SphericalMapOptions map_options(MapMethod method) {
  SphericalMapOptions o;
  o.method = method;
  o.fallback = false;  // exactly this start, so that two starts really differ
  o.flow_budget_seconds = 0;
  o.chain_budget_seconds = 0;
  o.canonical.method = CanonicalMap::Isometric;
  o.canonical.budget_seconds = 0;
  return o;
}

Eigen::VectorXd log_invariants(const Mesh& mesh, const SphericalMapResult& map) {
  ShFitOptions fit;
  fit.lmax = 8;
  fit.regularization = 1e-1;
  const Eigen::VectorXd xi = fit_spherical_harmonics(mesh, map.sphere, fit).invariants;
  return xi.segment(1, xi.size() - 1).array().log();
}

// Two different starts (the conformal cMCF map and the one-shot linear map) relax to one map: the same energy and
// the same ξ. Measured (bench/canonical_map_bench on real spines): max |Δ log ξ| 0.0000–0.0055 where both converge.
void expect_start_independent(const Mesh& mesh, double tolerance, MapMethod other = MapMethod::Linear) {
  const SphericalMapResult a = compute_spherical_map(mesh, map_options(MapMethod::Cmcf));
  const SphericalMapResult b = compute_spherical_map(mesh, map_options(other));
  expect_bijective(a);
  expect_bijective(b);
  std::printf("[canonical] cmcf start E %.4g -> %.6f (%d steps, %s); %s start E %.4g -> %.6f (%d steps, %s)\n",
              a.canonical.energy_start, a.canonical.energy, a.canonical.iterations, to_string(a.canonical.stop),
              to_string(other), b.canonical.energy_start, b.canonical.energy, b.canonical.iterations,
              to_string(b.canonical.stop));
  ASSERT_TRUE(a.canonical.converged);
  ASSERT_TRUE(b.canonical.converged);
  EXPECT_NE(a.canonical.energy_start, b.canonical.energy_start);  // the starts really differ
  EXPECT_NEAR(a.canonical.energy, b.canonical.energy, 1e-4 * a.canonical.energy);
  const Eigen::VectorXd la = log_invariants(mesh, a), lb = log_invariants(mesh, b);
  EXPECT_LT((la - lb).cwiseAbs().maxCoeff(), tolerance) << la.transpose() << "\n" << lb.transpose();
}

// An egg-like shape without mirror symmetry: every ξ(l) is well above zero (an ellipsoid's odd ξ are round-off,
// whose logarithms are noise).
Mesh asymmetric_blob() {
  return testing::deformed_icosphere(3, [](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(2.0 * p.x() + 0.4 * p.x() * p.x(), 0.7 * p.y() + 0.25 * p.x() * p.y(),
                           0.5 * p.z() + 0.15 * p.y() * p.y());
  });
}

TEST(CanonicalMap, DoesNotDependOnTheStartOnAnAsymmetricBlob) { expect_start_independent(asymmetric_blob(), 0.01); }

TEST(CanonicalMap, DoesNotDependOnTheStartOnARealSpine) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const auto path = *testing::shared_data_dir() / "hard" / "hvcl_spines" / "spine_1.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
  expect_start_independent(read_mesh_file(path).mesh, 0.01);
}

// The progressive embedding (the chain's last resort) starves whole regions to 1e-19 of their area (E ~ 1e19): the
// barrier-dominated case that needs Marquardt-scaled damping and step extrapolation (canonical_map.hpp). Measured
// (bench/canonical_map_bench spine_2.off --starts cmcf,progressive): 131 steps to the cMCF start's energy 4.6284;
// without the two, 200 steps ended at E 304.
TEST(CanonicalMap, ReachesTheSameMapFromTheProgressiveEmbeddingOnARealSpine) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const auto path = *testing::shared_data_dir() / "hard" / "hvcl_spines" / "spine_2.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
  expect_start_independent(read_mesh_file(path).mesh, 0.01, MapMethod::Progressive);
}

TEST(CanonicalMap, InvariantsDoNotMoveUnderRotation) {
  const Mesh m = asymmetric_blob();
  Mesh rotated = m;
  const Eigen::Matrix3d rot = testing::random_rotation(testing::test_seed(5));
  rotated.vertices = (m.vertices * rot.transpose()).eval();
  const SphericalMapResult a = compute_spherical_map(m, map_options(MapMethod::Cmcf));
  const SphericalMapResult b = compute_spherical_map(rotated, map_options(MapMethod::Cmcf));
  ASSERT_TRUE(a.canonical.converged);
  ASSERT_TRUE(b.canonical.converged);
  EXPECT_LT((log_invariants(m, a) - log_invariants(rotated, b)).cwiseAbs().maxCoeff(), 0.01);
}

// The chain's own map (cMCF, no canonical relaxation): the start the relaxation tests step from.
SphericalMapResult conformal_start(const Mesh& m) {
  SphericalMapOptions o = map_options(MapMethod::Cmcf);
  o.canonical.method = CanonicalMap::None;
  return compute_spherical_map(m, o);
}

TEST(CanonicalMap, EveryStepKeepsTheMapBijective) {
  // A long thin shape whose conformal start starves its ends: many steps, many halvings; each accepted one bijective.
  const Mesh m = testing::make_ellipsoid(3.0, 0.5, 0.5, 3);
  const SphericalMapResult start = conformal_start(m);
  ASSERT_TRUE(start.ok());
  Eigen::MatrixX3d u = start.sphere;
  CanonicalMapOptions c;
  c.budget_seconds = 0;
  for (int round = 0; round < 5; ++round) {
    c.max_iterations = 3;
    const double before = spherical::canonical_map_energy(u, m.vertices, m.faces, c, 1e-14);
    const CanonicalMapReport r = spherical::relax_to_canonical_map(u, m.vertices, m.faces, c, 1e-14);
    EXPECT_EQ(spherical::count_bad_sphere_faces(u, m.faces, 1e-14), 0);
    EXPECT_LE(r.energy, before);
    EXPECT_NEAR(r.energy, spherical::canonical_map_energy(u, m.vertices, m.faces, c, 1e-14), 1e-9 * r.energy);
  }
}

// The request's deadline binds the relaxation too (its CPU budget alone could run for 6 s per 10K vertices past it):
// an expired deadline stops it before the first step, with the start map untouched.
TEST(CanonicalMap, StopsAtTheRequestDeadline) {
  const Mesh m = testing::make_ellipsoid(3.0, 0.5, 0.5, 3);
  const SphericalMapResult start = conformal_start(m);
  ASSERT_TRUE(start.ok());
  Eigen::MatrixX3d u = start.sphere;
  const CanonicalMapReport r = spherical::relax_to_canonical_map(
      u, m.vertices, m.faces, CanonicalMapOptions{}, 1e-14, Deadline::after(std::chrono::duration<double>(0)));
  EXPECT_EQ(r.stop, CanonicalMapStop::TimeBudget);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(u, start.sphere);
}

}  // namespace
}  // namespace wish
