// Möbius normalisation (mobius.hpp; docs/design/spherical-map.md §8.3): the area-centre balancing must reach its fixed point
// on maps whose weight sits near two antipodal caps — the maps of elongated shapes, where the damped fixed-point
// iteration it replaced stalled above the tolerance after 500 steps — and that fixed point is the Douady–Earle
// barycentre, unique up to a rotation whatever boost the map started with.
#include <cmath>

#include <gtest/gtest.h>

#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/mobius.hpp"

namespace wish {
namespace {

// T_a(u) = (1 − |a|²)(u − a)/|u − a|² − a on every row: the ball-preserving Möbius map sending a to 0.
Eigen::MatrixX3d boosted(const Eigen::MatrixX3d& sphere, const Eigen::Vector3d& a) {
  Eigen::MatrixX3d u = sphere;
  for (Eigen::Index i = 0; i < u.rows(); ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(u.row(i)) - a;
    u.row(i) = ((1 - a.squaredNorm()) * d / d.squaredNorm() - a).normalized().transpose();
  }
  return u;
}

// Weight concentrated near the poles z = ±1, as the vertex areas of a long shape's map are (S = Σ w u uᵀ then has
// an eigenvalue near 1 along z).
Eigen::VectorXd polar_weights(const Eigen::MatrixX3d& sphere, double sharpness) {
  Eigen::VectorXd w(sphere.rows());
  for (Eigen::Index i = 0; i < sphere.rows(); ++i) w(i) = std::exp(sharpness * (sphere(i, 2) * sphere(i, 2) - 1));
  return w;
}

TEST(MobiusBalance, WeightOnTwoAntipodalCapsIsBalancedInAFewNewtonSteps) {
  const Mesh ico = make_icosphere(3);
  const Eigen::VectorXd w = polar_weights(ico.vertices, 200.0);
  const Eigen::Matrix3d s = ico.vertices.transpose() * (w / w.sum()).asDiagonal() * ico.vertices;
  ASSERT_GT(s(2, 2), 0.99);  // the hard case: almost all weight on the z axis
  Eigen::MatrixX3d u = boosted(ico.vertices, Eigen::Vector3d(0.05, -0.1, 0.3));
  ASSERT_GT(Eigen::Vector3d(u.transpose() * (w / w.sum())).norm(), 0.1);
  const spherical::MobiusResult r = spherical::mobius_balance(u, w);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.centroid, 1e-10);
  EXPECT_LE(r.iterations, 15);  // quadratic convergence (the fixed point a = 0.5 c ran out of 500 steps here)
  const MapQuality q = spherical::measure_map(ico.vertices, ico.faces, u, {});
  EXPECT_EQ(q.flipped_faces, 0);
  EXPECT_EQ(q.degree, 1);
}

TEST(MobiusBalance, TheBalancedMapIsUniqueUpToARotation) {
  // Two Möbius images of one map, balanced: the results differ by a rotation at most, so every pairwise angle
  // between vertex images agrees (and with it the invariants, which see the map only up to O(3)).
  const Mesh ico = make_icosphere(3);
  const Eigen::VectorXd w = polar_weights(ico.vertices, 5.0);
  Eigen::MatrixX3d first = boosted(ico.vertices, Eigen::Vector3d(0.4, 0.1, -0.2));
  Eigen::MatrixX3d second = boosted(ico.vertices, Eigen::Vector3d(-0.3, 0.5, 0.35));
  ASSERT_TRUE(spherical::mobius_balance(first, w).converged);
  ASSERT_TRUE(spherical::mobius_balance(second, w).converged);
  const Eigen::MatrixXd gram_first = first * first.transpose();
  const Eigen::MatrixXd gram_second = second * second.transpose();
  EXPECT_LT((gram_first - gram_second).cwiseAbs().maxCoeff(), 1e-8);
  // ... and the balanced map is not the map it started from (the boosts really moved it).
  const Eigen::MatrixXd gram_boosted = boosted(ico.vertices, Eigen::Vector3d(0.4, 0.1, -0.2)) *
                                       boosted(ico.vertices, Eigen::Vector3d(0.4, 0.1, -0.2)).transpose();
  EXPECT_GT((gram_first - gram_boosted).cwiseAbs().maxCoeff(), 1e-2);
}

TEST(MobiusBalance, ABalancedMapIsLeftAsItIs) {
  const Mesh ico = make_icosphere(2);
  Eigen::MatrixX3d u = ico.vertices;
  const spherical::MobiusResult r = spherical::mobius_balance(u, Eigen::VectorXd::Ones(u.rows()));
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ((u - ico.vertices).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace wish
