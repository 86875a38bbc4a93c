// The SH coefficients in the first-order-ellipsoid frame (core/sh/sh_canonical_frame.hpp): the same for every
// rigid motion of the object and every rotation of its sphere map, with the ambiguities reported.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "core/mesh/icosphere.hpp"
#include "core/sh/sh_basis.hpp"
#include "core/sh/sh_canonical_frame.hpp"
#include "core/sh/sh_fit.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

// An ellipsoid of distinct semi-axes (1.3, 1.0, 0.7) with a bump off every symmetry plane, over icosphere(level),
// with the icosphere directions as its analytic sphere map.
Mesh bumpy_ellipsoid(int level, Eigen::MatrixX3d& sphere, double bump = 0.25) {
  Mesh m = make_icosphere(level);
  sphere = m.vertices;
  const Eigen::Vector3d dir = Eigen::Vector3d(0.5, 0.6, 0.62).normalized();
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i) {
    const Eigen::Vector3d u = sphere.row(i);
    const double r = 1.0 + bump * std::exp(4.0 * (u.dot(dir) - 1.0));
    m.vertices.row(i) = (Eigen::Vector3d(1.3, 1.0, 0.7).asDiagonal() * (r * u)).transpose();
  }
  return m;
}

TEST(ShCanonicalFrame, SameForEveryRigidMotionAndMapRotation) {
  const unsigned seed = wish::testing::test_seed();
  std::printf("seed %u\n", seed);
  Eigen::MatrixX3d sphere;
  const Mesh mesh = bumpy_ellipsoid(4, sphere);
  ShFitOptions o;
  o.lmax = 8;
  const CanonicalShFrame base = canonical_sh_frame(fit_spherical_harmonics(mesh, sphere, o), mesh);
  std::printf("semi-axes %.4f %.4f %.4f, axis gap %.3f, sign margin %.3f\n", base.semi_axes(0), base.semi_axes(1),
              base.semi_axes(2), base.axis_gap, base.sign_margin);
  // The ellipsoid's axes, longest first; the chosen signs make the skewness of axes 1 and 2 non-negative.
  EXPECT_GT(base.semi_axes(0), base.semi_axes(1));
  EXPECT_NEAR(base.semi_axes(0), 1.3, 0.1);  // the ellipsoid the bump sits on
  EXPECT_NEAR(base.semi_axes(2), 0.7, 0.1);
  EXPECT_GT(base.semi_axes(1), base.semi_axes(2));
  EXPECT_GE(base.skewness(0), 0);
  EXPECT_GE(base.skewness(1), 0);
  EXPECT_GT(base.axis_gap, 0.1);
  EXPECT_GT(base.sign_margin, 1e-3);
  EXPECT_FALSE(base.parameter_reflected);
  EXPECT_NEAR(base.object_rotation.determinant(), 1.0, 1e-12);
  // In the frame the degree-1 part is diagonal: x1'(u') = Σ u'.
  const auto basis = ShBasis::get(1);
  Eigen::Matrix3d S1;
  for (int d = 0; d < 3; ++d) S1.col(d) = basis->real(Eigen::Vector3d::Unit(d)).segment(1, 3);
  const Eigen::Matrix3d G = base.coefficients.block(1, 0, 3, 3).transpose() * S1;
  EXPECT_LT((G - Eigen::Matrix3d(G.diagonal().asDiagonal())).norm(), 1e-10 * G.norm());
  for (unsigned t = 0; t < 3; ++t) {
    const Eigen::Matrix3d R = wish::testing::random_rotation(seed + t);
    Mesh moved = mesh;
    moved.vertices = (mesh.vertices * R.transpose()).rowwise() + Eigen::RowVector3d(3.0, -7.0, 11.0);
    const Eigen::MatrixX3d rotated_map = sphere * wish::testing::random_rotation(seed + 100 + t).transpose();
    const CanonicalShFrame f = canonical_sh_frame(fit_spherical_harmonics(moved, rotated_map, o), moved);
    // Degree 0 is the position (translated); every other coefficient is the same.
    const Eigen::MatrixX3d a = base.coefficients.bottomRows(base.coefficients.rows() - 1);
    const Eigen::MatrixX3d b = f.coefficients.bottomRows(f.coefficients.rows() - 1);
    EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-9 * a.cwiseAbs().maxCoeff()) << "seed " << seed + t;
    EXPECT_NEAR(f.sign_margin, base.sign_margin, 1e-9);
  }
}

TEST(ShCanonicalFrame, ScalingScalesCoefficientsAndAMirrorImageIsNotTheShape) {
  Eigen::MatrixX3d sphere;
  const Mesh mesh = bumpy_ellipsoid(3, sphere);
  ShFitOptions o;
  o.lmax = 6;
  const CanonicalShFrame base = canonical_sh_frame(fit_spherical_harmonics(mesh, sphere, o), mesh);
  Mesh scaled = mesh;
  scaled.vertices *= 2.5;
  const CanonicalShFrame s = canonical_sh_frame(fit_spherical_harmonics(scaled, sphere, o), scaled);
  EXPECT_LT((s.coefficients - 2.5 * base.coefficients).cwiseAbs().maxCoeff(), 1e-9 * s.coefficients.cwiseAbs().maxCoeff());
  // The frame is a proper rotation: the mirror image of a chiral shape keeps its handedness in the coefficients
  // (features of the two differ), while its ellipsoid is the same.
  Mesh mirrored = mesh;
  mirrored.vertices.col(0) *= -1;
  mirrored.faces.col(1).swap(mirrored.faces.col(2));
  Eigen::MatrixX3d mirrored_map = sphere;
  mirrored_map.col(0) *= -1;  // an orientation-preserving map of the mirrored surface
  const CanonicalShFrame m = canonical_sh_frame(fit_spherical_harmonics(mirrored, mirrored_map, o), mirrored);
  EXPECT_LT((m.semi_axes - base.semi_axes).norm(), 1e-9);
  EXPECT_GT((m.coefficients.bottomRows(m.coefficients.rows() - 1) - base.coefficients.bottomRows(base.coefficients.rows() - 1))
                .cwiseAbs().maxCoeff(), 1e-3);
}

TEST(ShCanonicalFrame, FeaturesSelectDegreesInNamedOrder) {
  Eigen::MatrixX3d c(sh_count(3), 3);
  for (Eigen::Index j = 0; j < c.rows(); ++j)
    for (int a = 0; a < 3; ++a) c(j, a) = 10.0 * static_cast<double>(j) + a;
  const Eigen::VectorXd f = canonical_sh_features(c, 2, 3);
  const auto names = canonical_sh_feature_names(2, 3);
  ASSERT_EQ(f.size(), 3 * (16 - 4));
  ASSERT_EQ(names.size(), static_cast<std::size_t>(f.size()));
  EXPECT_EQ(names.front(), "csh_2_-2_x");
  EXPECT_EQ(f(0), 10.0 * sh_index(2, -2));
  EXPECT_EQ(names.back(), "csh_3_3_z");
  EXPECT_EQ(f(f.size() - 1), 10.0 * sh_index(3, 3) + 2);
  EXPECT_THROW(canonical_sh_features(c, 0, 3), InvalidInputError);
  EXPECT_THROW(canonical_sh_features(c, 1, 4), InvalidInputError);
}

}  // namespace
}  // namespace wish
