// Surfaces of voxelised analytic shapes: a sphere and ellipsoids at isotropic and anisotropic spacing must give a
// closed, manifold, outward genus-0 mesh whose enclosed volume matches the voxel object's and whose area and volume
// match the analytic shape's within the tolerances stated in core/volume/object_surface.hpp; their ξ(l) must be
// close to the analytic ellipsoid's. A torus is reported with genus 1; two touching labels give two surfaces.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "core/common/errors.hpp"
#include "core/pipeline/pipeline.hpp"
#include "core/volume/label_objects.hpp"
#include "core/volume/object_surface.hpp"
#include "core/volume/surface_topology.hpp"
#include "tests/testing/test_data.hpp"

namespace wish::volume {
namespace {

// Voxel (i, j, k) is inside when its centre spacing ⊙ (i, j, k) lies in the ellipsoid with semi-axes `axes` (physical
// units) centred in the grid, with `margin` empty voxels around it.
LabelImage voxelise_ellipsoid(const Eigen::Vector3d& axes, const Eigen::Vector3d& spacing, std::uint32_t label = 1, int margin = 3) {
  LabelImage image;
  image.spacing = spacing;
  Eigen::Vector3d centre;
  for (int k = 0; k < 3; ++k) {
    image.dims[k] = static_cast<std::int64_t>(std::ceil(2 * axes(k) / spacing(k))) + 2 * margin + 1;
    centre(k) = 0.5 * static_cast<double>(image.dims[k] - 1) * spacing(k);
  }
  image.labels.assign(static_cast<std::size_t>(image.voxel_count()), 0);
  for (std::int64_t z = 0; z < image.dims[2]; ++z)
    for (std::int64_t y = 0; y < image.dims[1]; ++y)
      for (std::int64_t x = 0; x < image.dims[0]; ++x) {
        const Eigen::Vector3d p = spacing.cwiseProduct(Eigen::Vector3d(x, y, z)) - centre;
        if (p.cwiseQuotient(axes).squaredNorm() <= 1) image.labels[image.index(x, y, z)] = label;
      }
  return image;
}

struct Case {
  const char* name;
  Eigen::Vector3d axes, spacing;
};

class AnalyticShapes : public ::testing::TestWithParam<Case> {};

TEST_P(AnalyticShapes, ClosedGenusZeroWithAreaAndVolumeWithinTolerance) {
  const Case& c = GetParam();
  const LabelImage image = voxelise_ellipsoid(c.axes, c.spacing);
  const ObjectSet set = find_objects(image);
  ASSERT_EQ(set.objects.size(), 1u);
  EXPECT_FALSE(set.objects[0].truncated);
  SurfaceOptions options;
  options.target_vertices = 3000;
  const ObjectSurface s = object_surface(image, set, set.objects[0], options);
  ASSERT_TRUE(s.ok) << s.refusal_code << ": " << s.refusal;
  EXPECT_EQ(s.genus, 0);
  const SurfaceTopology t = analyze_surface(s.mesh);
  EXPECT_TRUE(t.closed_genus0()) << t.describe();
  EXPECT_LE(s.mesh.vertex_count(), 3000);
  const double pi = std::acos(-1.0);
  const double analytic_volume = 4.0 / 3.0 * pi * c.axes.prod();
  const Mesh reference = wish::testing::make_ellipsoid(c.axes(0), c.axes(1), c.axes(2), 6);
  const double analytic_area = mesh_area(reference);
  // Tolerances of object_surface.hpp: volume within 2 % of the voxels' and of the analytic shape's; area 0 to 12 %
  // above the analytic (the voxel staircase left after light smoothing only adds area).
  EXPECT_NEAR(s.volume / s.voxel_volume, 1.0, 0.02) << c.name;
  EXPECT_NEAR(s.volume / analytic_volume, 1.0, 0.02) << c.name;
  EXPECT_GE(s.area / analytic_area, 1.0) << c.name;
  EXPECT_LE(s.area / analytic_area, 1.12) << c.name;
  // The centroid in physical units is the grid centre.
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(set.objects[0].centroid(k), 0.5 * static_cast<double>(image.dims[k] - 1) * c.spacing(k), 0.05 * c.spacing(k));
  std::printf("%s: volume/voxels %.4f volume/analytic %.4f area/analytic %.4f (raw area/analytic %.4f), %lld vertices\n",
              c.name, s.volume / s.voxel_volume, s.volume / analytic_volume, s.area / analytic_area,
              s.raw_area / analytic_area, static_cast<long long>(s.mesh.vertex_count()));
}

INSTANTIATE_TEST_SUITE_P(
    Volume, AnalyticShapes,
    ::testing::Values(Case{"sphere_iso", {12, 12, 12}, {1, 1, 1}},
                      Case{"sphere_aniso", {12, 12, 12}, {1, 1, 2}},
                      Case{"ellipsoid_iso", {16, 11, 8}, {1, 1, 1}},
                      Case{"ellipsoid_aniso_nm", {240, 176, 120}, {16, 16, 15}}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(ObjectSurface, XiCloseToTheAnalyticEllipsoid) {
  const Eigen::Vector3d axes(16, 11, 8);
  const LabelImage image = voxelise_ellipsoid(axes, Eigen::Vector3d(1, 1, 1.5));
  const ObjectSet set = find_objects(image);
  ASSERT_EQ(set.objects.size(), 1u);
  SurfaceOptions options;
  options.target_vertices = 4000;
  const ObjectSurface s = object_surface(image, set, set.objects[0], options);
  ASSERT_TRUE(s.ok) << s.refusal;
  PipelineOptions p;
  p.sh.lmax = 8;
  const PipelineResult voxel = describe_mesh(s.mesh, p);
  const PipelineResult analytic = describe_mesh(wish::testing::make_ellipsoid(axes(0), axes(1), axes(2), 5), p);
  // xi(l) for l >= 1 is translation-invariant; compare shares of the total so the small size difference cancels.
  const double total_v = voxel.sh.invariants.tail(8).sum(), total_a = analytic.sh.invariants.tail(8).sum();
  for (int l = 1; l <= 8; ++l) {
    const double sv = voxel.sh.invariants(l) / total_v, sa = analytic.sh.invariants(l) / total_a;
    std::printf("l=%d share voxel %.5f analytic %.5f\n", l, sv, sa);
    EXPECT_NEAR(sv, sa, 0.01) << "degree " << l;
  }
}

LabelImage torus_image() {
  LabelImage image;
  image.dims = {32, 32, 14};
  image.labels.assign(32 * 32 * 14, 0);
  for (std::int64_t z = 0; z < 14; ++z)
    for (std::int64_t y = 0; y < 32; ++y)
      for (std::int64_t x = 0; x < 32; ++x) {
        const double r = std::hypot(x - 15.5, y - 15.5);
        image.labels[image.index(x, y, z)] = std::hypot(r - 10, z - 6.5) < 4 ? 7 : 0;
      }
  return image;
}

TEST(ObjectSurface, ATorusIsCutToGenusZeroAndTheRepairReported) {
  const LabelImage image = torus_image();
  ObjectOptions by_label;
  by_label.mode = ObjectMode::Labels;
  const ObjectSet set = find_objects(image, by_label);
  ASSERT_EQ(set.objects.size(), 1u);
  EXPECT_EQ(set.objects[0].id, 7u);
  const ObjectSurface s = object_surface(image, set, set.objects[0]);
  EXPECT_EQ(s.genus, 1);  // the voxel object's genus, before the repair
  ASSERT_TRUE(s.ok) << s.refusal;
  EXPECT_TRUE(s.repaired);
  // Cutting the tube (a cross-section, about 50 voxels) is far less than filling the hole (a disc of about 300).
  EXPECT_STREQ(s.repair.method(), "cut");
  EXPECT_EQ(s.voxels_meshed, set.objects[0].voxel_count - s.repair.removed);
  EXPECT_LT(s.repair.volume_change(), 0.05);
  bool listed = false;
  for (const auto& r : s.repairs) listed = listed || r == "removed the handles: " + s.repair.describe();
  EXPECT_TRUE(listed) << (s.repairs.empty() ? "" : s.repairs.back());
  EXPECT_TRUE(analyze_surface(s.mesh).closed_genus0());
}

TEST(ObjectSurface, HandleRepairOffOrOverTheBoundIsARefusalThatSaysWhatTheRepairWouldChange) {
  const LabelImage image = torus_image();
  const ObjectSet set = find_objects(image);
  const ObjectSurface repaired = object_surface(image, set, set.objects[0]);
  ASSERT_TRUE(repaired.ok);
  SurfaceOptions off;
  off.max_repair_share = 0;  // --no-close-handles
  const ObjectSurface refused = object_surface(image, set, set.objects[0], off);
  EXPECT_FALSE(refused.ok);
  EXPECT_EQ(refused.refusal_code, "genus_nonzero");
  EXPECT_NE(refused.refusal.find("genus 1"), std::string::npos) << refused.refusal;
  EXPECT_NE(refused.refusal.find("it touches no other object"), std::string::npos) << refused.refusal;
  EXPECT_NE(refused.refusal.find("the repair that removes the handles (" + repaired.repair.describe() +
                                 ") is not applied: handle repair is off (--no-close-handles)"),
            std::string::npos)
      << refused.refusal;
  SurfaceOptions tight;
  tight.max_repair_share = repaired.repair.volume_change() / 2;
  const ObjectSurface over = object_surface(image, set, set.objects[0], tight);
  EXPECT_FALSE(over.ok);
  EXPECT_NE(over.refusal.find("changes more than the bound of"), std::string::npos) << over.refusal;
  SurfaceOptions any;
  any.max_repair_share = std::numeric_limits<double>::infinity();  // --close-handles
  EXPECT_TRUE(object_surface(image, set, set.objects[0], any).ok);
}

TEST(ObjectSurface, ASmallTunnelIsFilledByDefaultAndListedWithItsVolume) {
  // A ball with a one-voxel tunnel drilled through it: genus 1; one plug voxel where the tunnel is narrowest fills it.
  LabelImage image = voxelise_ellipsoid({8, 8, 8}, {1, 1, 1});
  const std::int64_t c = image.dims[0] / 2;
  for (std::int64_t z = 0; z < image.dims[2]; ++z) image.labels[image.index(c, c, z)] = 0;
  const ObjectSet set = find_objects(image);
  ASSERT_EQ(set.objects.size(), 1u);
  const ObjectSurface s = object_surface(image, set, set.objects[0]);
  EXPECT_EQ(s.genus, 1);
  ASSERT_TRUE(s.ok) << s.refusal;
  EXPECT_STREQ(s.repair.method(), "fill");
  EXPECT_EQ(s.repair.fills, 1);
  EXPECT_EQ(s.voxels_meshed, set.objects[0].voxel_count + s.repair.added);
  EXPECT_NEAR(s.repair.volume_change(),
              static_cast<double>(s.repair.added) / static_cast<double>(set.objects[0].voxel_count), 1e-15);
  EXPECT_NE(s.repair.describe().find("filled 1 tunnel (+"), std::string::npos) << s.repair.describe();
}

// n balls of radius r (voxels) on a ring in one mask, neighbours overlapping by `overlap`: cells touching in a loop.
LabelImage ring_of_balls(int n, double r, double overlap) {
  const double pi = std::acos(-1.0);
  const double radius = (2 * r - overlap) / (2 * std::sin(pi / n));
  LabelImage image;
  image.dims = {64, 64, 24};
  image.labels.assign(static_cast<std::size_t>(image.voxel_count()), 0);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d c(32.31 + radius * std::cos(2 * pi * k / n), 32.17 + radius * std::sin(2 * pi * k / n), 11.73);
    for (std::int64_t z = 0; z < image.dims[2]; ++z)
      for (std::int64_t y = 0; y < image.dims[1]; ++y)
        for (std::int64_t x = 0; x < image.dims[0]; ++x)
          if ((Eigen::Vector3d(static_cast<double>(x), static_cast<double>(y), static_cast<double>(z)) - c).norm() <= r)
            image.labels[image.index(x, y, z)] = 255;
  }
  return image;
}

TEST(ObjectSurface, TouchingBallsInALoopAreCutAtAContact) {
  // Balls of radius 8 overlapping by one voxel, in a loop of 4 or 6: genus 1. Cutting one contact removes a disc of
  // a few voxels; filling the loop's hole would add more (41 and 208 voxels).
  for (int n : {4, 6}) {
    const LabelImage ring = ring_of_balls(n, 8, 1);
    const ObjectSet set = find_objects(ring);
    ASSERT_EQ(set.objects.size(), 1u);
    const ObjectSurface s = object_surface(ring, set, set.objects[0]);
    EXPECT_EQ(s.genus, 1) << n;
    ASSERT_TRUE(s.ok) << s.refusal;
    EXPECT_STREQ(s.repair.method(), "cut");
    EXPECT_LT(s.repair.removed, 40) << n;  // one contact: a disc of radius about 3 voxels
    EXPECT_LT(s.repair.removed, s.repair.fill_every_tunnel) << n;
  }
}

TEST(ObjectSurface, AHandleAgainstAnotherLabelIsReportedWithTheTouchingVoxels) {
  // A torus (label 7) with a ball (label 8) resting against its outer side.
  LabelImage image;
  image.dims = {40, 32, 14};
  image.labels.assign(static_cast<std::size_t>(image.voxel_count()), 0);
  std::int64_t touching = 0;
  for (std::int64_t z = 0; z < 14; ++z)
    for (std::int64_t y = 0; y < 32; ++y)
      for (std::int64_t x = 0; x < 40; ++x) {
        const double r = std::hypot(x - 15.5, y - 15.5);
        if (std::hypot(r - 10, z - 6.5) < 4) image.labels[image.index(x, y, z)] = 7;
        else if (std::hypot(std::hypot(x - 32.5, y - 15.5), z - 6.5) < 4.2) image.labels[image.index(x, y, z)] = 8;
      }
  for (std::int64_t z = 0; z < 14; ++z)
    for (std::int64_t y = 0; y < 32; ++y)
      for (std::int64_t x = 1; x + 1 < 40; ++x)
        touching += image.at(x, y, z) == 7 && (image.at(x + 1, y, z) == 8 || image.at(x - 1, y, z) == 8 ||
                                               (y > 0 && image.at(x, y - 1, z) == 8) || (y < 31 && image.at(x, y + 1, z) == 8) ||
                                               (z > 0 && image.at(x, y, z - 1) == 8) || (z < 13 && image.at(x, y, z + 1) == 8));
  ASSERT_GT(touching, 0);
  const ObjectSet set = find_objects(image);
  ASSERT_EQ(set.objects.size(), 2u);
  SurfaceOptions off;
  off.max_repair_share = 0;
  const ObjectSurface s = object_surface(image, set, set.objects[0], off);
  EXPECT_FALSE(s.ok);
  EXPECT_EQ(s.touching_voxels, touching);
  EXPECT_EQ(s.touching_ids, std::vector<std::uint32_t>{8});
  EXPECT_NE(s.refusal.find("it touches 1 other object(s) on " + std::to_string(touching) + " voxels (8)"), std::string::npos)
      << s.refusal;
}

TEST(ObjectSurface, TwoTouchingLabelsGiveTwoSeparateClosedSurfaces) {
  LabelImage image;
  image.dims = {30, 16, 16};
  image.labels.assign(30 * 16 * 16, 0);
  for (std::int64_t z = 3; z < 13; ++z)
    for (std::int64_t y = 3; y < 13; ++y)
      for (std::int64_t x = 3; x < 27; ++x) image.labels[image.index(x, y, z)] = x < 15 ? 4 : 9;  // face to face
  const ObjectSet set = find_objects(image);
  EXPECT_EQ(set.mode, ObjectMode::Labels);
  ASSERT_EQ(set.objects.size(), 2u);
  EXPECT_EQ(set.objects[0].id, 4u);
  EXPECT_EQ(set.objects[1].id, 9u);
  for (const auto& o : set.objects) {
    EXPECT_EQ(o.voxel_count, 12 * 10 * 10);
    const ObjectSurface s = object_surface(image, set, o);
    ASSERT_TRUE(s.ok) << s.refusal;
    EXPECT_TRUE(analyze_surface(s.mesh).closed_genus0());
    EXPECT_NEAR(s.volume / s.voxel_volume, 1.0, 0.05);
    // The two boxes share a face: each surface stays on its own side of the plane x = 14.5 between them (up to the
    // quarter voxel that smoothing moves the rounded edges).
    const double xmin = s.mesh.vertices.col(0).minCoeff(), xmax = s.mesh.vertices.col(0).maxCoeff();
    if (o.id == 4) EXPECT_LE(xmax, 14.75);
    else EXPECT_GE(xmin, 14.25);
  }
}

TEST(LabelObjects, MaskComponentsFiltersAndTruncation) {
  LabelImage image;
  image.dims = {20, 10, 10};
  image.labels.assign(2000, 0);
  auto block = [&](std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1) {
    for (std::int64_t z = 2; z < 6; ++z)
      for (std::int64_t y = y0; y < y1; ++y)
        for (std::int64_t x = x0; x < x1; ++x) image.labels[image.index(x, y, z)] = 1;
  };
  block(2, 6, 2, 6);    // 64 voxels, inside
  block(8, 10, 2, 4);   // 16 voxels, inside
  block(15, 20, 2, 6);  // 80 voxels, touches x = 19
  image.labels[image.index(7, 7, 7)] = 1;  // diagonal to nothing: its own component of 1 voxel
  const ObjectSet by_default = find_objects(image);  // the 1-voxel component is a speck
  EXPECT_EQ(by_default.objects.size(), 3u);
  EXPECT_EQ(by_default.dropped_specks, 1);
  ObjectOptions every;
  every.min_voxels = 0;
  const ObjectSet all = find_objects(image, every);
  EXPECT_EQ(all.mode, ObjectMode::Components);
  ASSERT_EQ(all.objects.size(), 4u);
  EXPECT_EQ(all.objects[0].voxel_count, 64);
  EXPECT_TRUE(all.objects[2].truncated || all.objects[3].truncated);
  ObjectOptions options;
  options.min_voxels = 10;
  options.drop_truncated = true;
  const ObjectSet kept = find_objects(image, options);
  EXPECT_EQ(kept.objects.size(), 2u);
  EXPECT_EQ(kept.dropped_small, 1);
  EXPECT_EQ(kept.dropped_truncated, 1);
  options = every;
  options.label_ids = {1};
  EXPECT_EQ(find_objects(image, options).objects.size(), 1u);
  options = every;
  options.max_objects = 3;
  EXPECT_THROW(find_objects(image, options), LimitExceededError);
  // Forced label mode: the mask is one object (value 1) whatever its components.
  options = {};
  options.mode = ObjectMode::Labels;
  EXPECT_EQ(find_objects(image, options).objects.size(), 1u);
}

}  // namespace
}  // namespace wish::volume
