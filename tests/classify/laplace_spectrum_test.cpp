// ShapeDNA (core/classify/laplace_spectrum.hpp) against analytic truths: the unit sphere's l(l+1) with
// multiplicity 2l+1, invariance to scale, and to an exact isometric bending of a closed surface.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "core/classify/laplace_spectrum.hpp"
#include "core/common/errors.hpp"
#include "core/mesh/icosphere.hpp"

namespace wish {
namespace {

// A latitude-longitude sphere: `rings` rings of `segments` vertices between two poles, outward triangles. Ring i
// (1-based) lies at colatitude i π / (rings + 1), so every ring is a planar loop of vertices.
Mesh uv_sphere(int rings, int segments) {
  Mesh m;
  m.vertices.resize(2 + rings * segments, 3);
  m.vertices.row(0) = Eigen::RowVector3d(0, 0, 1);
  for (int i = 0; i < rings; ++i) {
    const double t = (i + 1) * std::numbers::pi / (rings + 1);
    for (int j = 0; j < segments; ++j) {
      const double p = 2 * std::numbers::pi * j / segments;
      m.vertices.row(1 + i * segments + j) = Eigen::RowVector3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
    }
  }
  const int south = 1 + rings * segments;
  m.vertices.row(south) = Eigen::RowVector3d(0, 0, -1);
  std::vector<Eigen::RowVector3i> f;
  const auto v = [&](int i, int j) { return 1 + i * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) f.emplace_back(0, v(0, j), v(0, j + 1));
  for (int i = 0; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      f.emplace_back(v(i, j), v(i + 1, j), v(i + 1, j + 1));
      f.emplace_back(v(i, j), v(i + 1, j + 1), v(i, j + 1));
    }
  for (int j = 0; j < segments; ++j) f.emplace_back(south, v(rings - 1, j + 1), v(rings - 1, j));
  m.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t k = 0; k < f.size(); ++k) m.faces.row(static_cast<Eigen::Index>(k)) = f[k];
  return m;
}

TEST(LaplaceSpectrum, UnitSphereHasLTimesLPlusOneWithMultiplicity) {
  const Mesh sphere = make_icosphere(3);  // 642 vertices
  const LaplaceSpectrum s = laplace_spectrum(sphere, 15);  // l = 1..3: 3 + 5 + 7 values
  std::printf("zero mode %.2e, residual %.2e, %d cycles; lambda:", s.zero_mode, s.max_residual, s.cycles);
  for (Eigen::Index i = 0; i < s.values.size(); ++i) std::printf(" %.4f", s.values(i));
  std::printf("\n");
  EXPECT_NEAR(s.zero_mode, 0.0, 1e-8);
  int i = 0;
  for (int l = 1; l <= 3; ++l)
    for (int m = 0; m < 2 * l + 1; ++m, ++i) {
      // The discretisation error of the cotan Laplacian grows with l and shrinks with the level (measured on level
      // 4: 0.1 % at l = 1, 0.5 % at l = 3, 0.8 % at l = 4; level 3 is coarser); the clusters stay separate.
      EXPECT_NEAR(s.values(i), l * (l + 1), 0.03 * l * (l + 1)) << "l " << l << " m " << m;
    }
}

TEST(LaplaceSpectrum, ScaleAndRigidMotionLeaveItUnchanged) {
  Mesh m = make_icosphere(2);
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i) {  // an ellipsoid: no degenerate clusters to mix
    m.vertices(i, 0) *= 1.6;
    m.vertices(i, 2) *= 0.7;
  }
  const LaplaceSpectrum base = laplace_spectrum(m, 8);
  Mesh scaled = m;
  scaled.vertices = (7.25 * m.vertices).rowwise() + Eigen::RowVector3d(1, -2, 3);
  const LaplaceSpectrum s = laplace_spectrum(scaled, 8);
  EXPECT_LT((s.values - base.values).cwiseAbs().maxCoeff(), 1e-7 * base.values.maxCoeff());
}

TEST(LaplaceSpectrum, IsometricBendingLeavesItUnchanged) {
  // The cap of a sphere above a ring of vertices, reflected through the ring's plane, folds the sphere into a
  // dimpled one: every edge keeps its length (the cap moves rigidly, the ring stays), so the metric — and the
  // spectrum — are those of the sphere, while the shape in space is another (its volume drops by a third here).
  const Mesh sphere = uv_sphere(15, 32);
  Mesh dimpled = sphere;
  const double plane = sphere.vertices(1 + 3 * 32, 2);  // ring 4, z = cos(4π/16)
  for (Eigen::Index i = 0; i < dimpled.vertex_count(); ++i)
    if (dimpled.vertices(i, 2) > plane + 1e-12) dimpled.vertices(i, 2) = 2 * plane - dimpled.vertices(i, 2);
  const LaplaceSpectrum a = laplace_spectrum(sphere, 8), b = laplace_spectrum(dimpled, 8);
  std::printf("sphere lambda_1..3 %.5f %.5f %.5f, dimpled %.5f %.5f %.5f\n", a.values(0), a.values(1), a.values(2),
              b.values(0), b.values(1), b.values(2));
  EXPECT_LT((a.values - b.values).cwiseAbs().maxCoeff(), 1e-6 * a.values.maxCoeff());
  // Not a vacuous check: the first eigenvalues are the sphere's l(l+1) to the mesh's accuracy.
  EXPECT_NEAR(a.values(0), 2.0, 0.05);
}

TEST(LaplaceSpectrum, RefusesBadCountsAndTinyMeshes) {
  const Mesh m = make_icosphere(1);  // 42 vertices
  EXPECT_THROW(laplace_spectrum(m, 0), InvalidInputError);
  EXPECT_THROW(laplace_spectrum(m, kMaxSpectrumCount + 1), InvalidInputError);
  EXPECT_THROW(laplace_spectrum(m, 42), WishError);
  EXPECT_EQ(laplace_spectrum(m, 10).values.size(), 10);
}

}  // namespace
}  // namespace wish
