#include <gtest/gtest.h>

#include <numbers>

#include "core/classify/global_descriptors.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

TEST(GlobalDescriptors, SphereValues) {
  const Mesh sphere = testing::make_ellipsoid(2, 2, 2, 5);
  const Eigen::VectorXd g = global_shape_descriptors(sphere);
  EXPECT_NEAR(g(kGlobalVolume), 4.0 / 3 * std::numbers::pi * 8, 0.05);
  EXPECT_NEAR(g(kGlobalArea), 4 * std::numbers::pi * 4, 0.1);
  EXPECT_NEAR(g(kGlobalSphericity), 1.0, 1e-3);
  EXPECT_NEAR(g(kGlobalElongation), 1.0, 1e-3);
  EXPECT_NEAR(g(kGlobalEllipsoidAreaRatio), 1.0, 1e-2);
  EXPECT_NEAR(g(kGlobalMeanCurvatureRatio), 1.0, 1e-2);
  EXPECT_NEAR(g(kGlobalConcaveAreaFraction), 0.0, 1e-9);
}

TEST(GlobalDescriptors, EllipsoidAxesAndInvariance) {
  Mesh m = testing::make_ellipsoid(4, 2, 1, 4);
  const Eigen::VectorXd g = global_shape_descriptors(m);
  EXPECT_NEAR(g(kGlobalElongation), 0.5, 0.01);
  EXPECT_NEAR(g(kGlobalFlatness), 0.5, 0.01);
  EXPECT_NEAR(g(kGlobalAxisRatio), 0.25, 0.01);
  // Rotation + translation: identical up to rounding; uniform scaling: scale-free entries identical.
  const Eigen::Matrix3d R = testing::random_rotation(testing::test_seed());
  Mesh moved = m;
  moved.vertices = (m.vertices * R.transpose()).rowwise() + Eigen::RowVector3d(10, -3, 7);
  const Eigen::VectorXd h = global_shape_descriptors(moved);
  for (int i = 0; i < kGlobalCount; ++i) EXPECT_NEAR(h(i), g(i), 1e-9 * std::max(1.0, std::abs(g(i)))) << global_descriptor_names()[i];
  Mesh scaled = m;
  scaled.vertices *= 3.0;
  const Eigen::VectorXd s = global_shape_descriptors(scaled);
  for (int i = 0; i < kGlobalCount; ++i)
    if (global_descriptor_is_scale_free(i)) {
      EXPECT_NEAR(s(i), g(i), 1e-9) << global_descriptor_names()[i];
    }
  EXPECT_NEAR(s(kGlobalVolume), 27 * g(kGlobalVolume), 1e-9 * s(kGlobalVolume));
}

}  // namespace
}  // namespace wish
