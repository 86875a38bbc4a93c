#pragma once
// Checks and test shapes shared by the spherical-map tests (one definition instead of a copy per file).
#include <gtest/gtest.h>

#include <Eigen/Core>

#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/spherical_map.hpp"

namespace wish::testing {

// The unit icosphere of `level` with every vertex moved by p ↦ f(p).
template <class F>
Mesh deformed_icosphere(int level, F f) {
  Mesh m = make_icosphere(level);
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i)
    m.vertices.row(i) = f(Eigen::Vector3d(m.vertices.row(i))).transpose();
  return m;
}

// A bijective map onto the sphere: every vertex finite, no face flipped or degenerate, degree 1.
inline void expect_bijective(const MapQuality& q) {
  EXPECT_EQ(q.non_finite_vertices, 0);
  EXPECT_EQ(q.flipped_faces, 0);
  EXPECT_EQ(q.degenerate_faces, 0);
  EXPECT_EQ(q.degree, 1);
}

// ... and the chain says so: its result is ok and its verdict not Failed.
inline void expect_bijective(const SphericalMapResult& r) {
  expect_bijective(r.quality);
  EXPECT_TRUE(r.ok()) << to_string(r.failed_check) << ": " << (r.attempts.empty() ? "" : r.attempts.back().message);
  EXPECT_NE(r.verdict, MapVerdict::Failed);
}

}  // namespace wish::testing
