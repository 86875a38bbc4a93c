// Per-face distortion of a sphere map (map_verification.hpp): analytic cases, and measure_map's summaries are
// exactly the summaries of these arrays.
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/map_verification.hpp"

namespace wish::spherical {
namespace {

TEST(FaceDistortion, IdentityAndUniformScaleAreUndistorted) {
  const Mesh sphere = make_icosphere(2);
  for (double scale : {1.0, 3.5}) {
    const Eigen::MatrixX3d input = scale * sphere.vertices;
    const FaceDistortion d = face_distortion(input, sphere.faces, sphere.vertices);
    ASSERT_EQ(d.conformal.size(), sphere.faces.rows());
    ASSERT_EQ(d.area_ratio.size(), sphere.faces.rows());
    // K = (sp + sm) / (sp - sm) with sm = sqrt(|J|_F^2 - 2 |det J|): for a similarity sm is the square root of a
    // rounding error, so K - 1 is of the order sqrt(eps) ~ 1e-8, not eps (measured 1.8e-8 at scale 3.5).
    EXPECT_LT((d.conformal.array() - 1.0).abs().maxCoeff(), 1e-7) << "scale " << scale;
    EXPECT_LT((d.area_ratio.array() - 1.0).abs().maxCoeff(), 1e-12) << "scale " << scale;
  }
}

TEST(FaceDistortion, AnisotropicStretchIsMeasuredAndSummarisedByMeasureMap) {
  const Mesh sphere = make_icosphere(2);
  Eigen::MatrixX3d input = sphere.vertices;
  input.col(0) *= 2.0;  // an ellipsoid: the radial map to the sphere is not conformal
  const FaceDistortion d = face_distortion(input, sphere.faces, sphere.vertices);
  EXPECT_GE(d.conformal.minCoeff(), 1.0 - 1e-12);
  EXPECT_GT(d.conformal.maxCoeff(), 1.5);  // faces near the x poles are squeezed by about 2 in one direction
  EXPECT_LE(d.conformal.maxCoeff(), 2.0 + 1e-9);  // no face more than the stretch itself
  // Area shares: the weighted mean of the ratios with the input shares is 1.
  double input_total = 0, weighted = 0;
  for (Eigen::Index f = 0; f < sphere.faces.rows(); ++f) {
    const Eigen::Vector3d a = input.row(sphere.faces(f, 0)), b = input.row(sphere.faces(f, 1)), c = input.row(sphere.faces(f, 2));
    const double area = 0.5 * (b - a).cross(c - a).norm();
    input_total += area;
    weighted += area * d.area_ratio[f];
  }
  EXPECT_NEAR(weighted / input_total, 1.0, 1e-12);

  const MapQuality q = measure_map(input, sphere.faces, sphere.vertices, MapVerificationThresholds{});
  EXPECT_DOUBLE_EQ(q.conformal_mean, d.conformal.mean());
  EXPECT_EQ(q.conformal_max, d.conformal.maxCoeff());
  double log_sum = 0;
  for (Eigen::Index f = 0; f < d.area_ratio.size(); ++f) log_sum += std::abs(std::log(d.area_ratio[f]));
  EXPECT_NEAR(q.area_distortion, std::exp(log_sum / static_cast<double>(d.area_ratio.size())), 1e-14);
  EXPECT_GT(q.area_distortion, 1.05);
}

}  // namespace
}  // namespace wish::spherical
