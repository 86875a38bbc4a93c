// The objects a lab means (core/volume/specks_and_fragments.hpp): specks are dropped and listed, fragments near a
// dominant object are merged into it and listed as its pieces, and neither rule touches what it must not (separate
// objects of similar size, pieces beyond the gap, an explicit --min-voxels).
#include <gtest/gtest.h>

#include <cmath>

#include "core/volume/label_objects.hpp"
#include "core/volume/specks_and_fragments.hpp"

namespace wish::volume {
namespace {

LabelImage empty_image(std::int64_t n) {
  LabelImage image;
  image.dims = {n, n, n};
  image.labels.assign(static_cast<std::size_t>(n * n * n), 0);
  return image;
}

// A ball of `value` voxels with centres within `r` of c.
std::int64_t paint_ball(LabelImage& image, const Eigen::Vector3d& c, double r, std::uint32_t value) {
  std::int64_t n = 0;
  for (std::int64_t z = 0; z < image.dims[2]; ++z)
    for (std::int64_t y = 0; y < image.dims[1]; ++y)
      for (std::int64_t x = 0; x < image.dims[0]; ++x)
        if ((Eigen::Vector3d(static_cast<double>(x), static_cast<double>(y), static_cast<double>(z)) - c).norm() <= r) {
          n += image.labels[image.index(x, y, z)] == 0;
          image.labels[image.index(x, y, z)] = value;
        }
  return n;
}

void paint_box(LabelImage& image, std::array<std::int64_t, 3> lo, std::array<std::int64_t, 3> hi, std::uint32_t value) {
  for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
    for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
      for (std::int64_t x = lo[0]; x <= hi[0]; ++x) image.labels[image.index(x, y, z)] = value;
}

TEST(SpeckRule, TypicalObjectIgnoresSpecksAndTheBoundHasAFloor) {
  const SpeckRule one = speck_rule({20000, 1, 2, 1, 3});
  EXPECT_EQ(one.typical_voxels, 20000);
  EXPECT_EQ(one.below, 100);  // 0.5 % of 20000
  const SpeckRule many = speck_rule({5000, 4000, 6000, 3000, 300, 10});
  EXPECT_EQ(many.typical_voxels, 5000);  // the median of the four of at least 10 % of the largest
  EXPECT_EQ(many.below, 25);
  EXPECT_EQ(speck_rule({600}).below, kSpeckFloorVoxels);  // 0.5 % of 600 is 3: the floor of 8 holds
  EXPECT_EQ(speck_rule({}).below, 0);
}

TEST(Specks, AThresholdedCellWithSpecksIsOneObjectAndTheSpecksAreListed) {
  LabelImage image = empty_image(48);
  const std::int64_t cell = paint_ball(image, {20.3, 22.1, 24.7}, 12, 255);
  paint_box(image, {42, 3, 3}, {42, 3, 3}, 255);   // one voxel
  paint_box(image, {3, 42, 40}, {4, 42, 40}, 255);  // two
  paint_box(image, {40, 40, 4}, {41, 41, 4}, 255);  // four
  const ObjectSet set = find_objects(image);
  EXPECT_EQ(set.mode, ObjectMode::Components);
  EXPECT_EQ(set.found, 4);
  ASSERT_EQ(set.objects.size(), 1u);
  EXPECT_EQ(set.objects[0].voxel_count, cell);
  EXPECT_EQ(set.dropped_specks, 3);
  ASSERT_EQ(set.dropped.size(), 3u);
  for (const DroppedObject& d : set.dropped) {
    EXPECT_EQ(d.reason, DropReason::Speck);
    EXPECT_LE(d.object.voxel_count, 4);
    EXPECT_EQ(d.why.rfind(std::to_string(d.object.voxel_count) + " voxel", 0), 0u) << d.why;
  }
  // --min-voxels 0 keeps every one; --min-voxels 3 drops two as "small".
  ObjectOptions keep_all;
  keep_all.min_voxels = 0;
  EXPECT_EQ(find_objects(image, keep_all).objects.size(), 4u);
  ObjectOptions three;
  three.min_voxels = 3;
  const ObjectSet small = find_objects(image, three);
  EXPECT_EQ(small.objects.size(), 2u);
  EXPECT_EQ(small.dropped_small, 2);
  EXPECT_EQ(small.dropped_specks, 0);
  EXPECT_EQ(small.dropped[0].reason, DropReason::Small);
}

TEST(Specks, TinyLabelsAreSpecksToo) {
  LabelImage image = empty_image(40);
  paint_ball(image, {12, 12, 12}, 8, 3);
  paint_ball(image, {27, 27, 27}, 7, 5);
  paint_box(image, {35, 5, 5}, {36, 6, 5}, 9);  // 4 voxels
  const ObjectSet set = find_objects(image);
  EXPECT_EQ(set.mode, ObjectMode::Labels);
  ASSERT_EQ(set.objects.size(), 2u);
  ASSERT_EQ(set.dropped.size(), 1u);
  EXPECT_EQ(set.dropped[0].object.id, 9u);
  EXPECT_EQ(set.dropped[0].reason, DropReason::Speck);
}

TEST(Fragments, PiecesNearADominantObjectAreMergedAndListed) {
  LabelImage image = empty_image(56);
  const std::int64_t main = paint_ball(image, {24.2, 27.5, 26.9}, 13, 1);
  // A limb cut off the ball: a 3 x 3 x 6 bar whose near end leaves a gap of 2 background voxels to the ball.
  std::int64_t ball_max_x = 0;
  for (std::int64_t x = 0; x < 56; ++x)
    if (image.at(x, 27, 27)) ball_max_x = x;
  paint_box(image, {ball_max_x + 3, 26, 26}, {ball_max_x + 8, 28, 28}, 1);
  // A second bar 8 voxels away from the ball on the other side: not a fragment, and large enough not to be a speck.
  std::int64_t ball_min_x = 55;
  for (std::int64_t x = 55; x >= 0; --x)
    if (image.at(x, 27, 27)) ball_min_x = x;
  paint_box(image, {ball_min_x - 13, 26, 26}, {ball_min_x - 9, 29, 29}, 1);
  const ObjectSet set = find_objects(image);
  EXPECT_EQ(set.fragments_merged, 1);
  ASSERT_EQ(set.objects.size(), 2u);
  const VolumeObject& cell = set.objects[0].voxel_count > set.objects[1].voxel_count ? set.objects[0] : set.objects[1];
  ASSERT_EQ(cell.fragments.size(), 1u);
  EXPECT_EQ(cell.fragments[0].voxel_count, 3 * 3 * 6);
  EXPECT_EQ(cell.fragments[0].gap, 2);
  EXPECT_EQ(cell.voxel_count, main + 54);
  EXPECT_EQ(cell.bbox_max[0], ball_max_x + 8);  // the box includes the piece
  // The piece's voxels carry the object's id, so its surface and its class map include them.
  EXPECT_EQ(set.id_at(image, image.index(ball_max_x + 5, 27, 27)), cell.id);
  // With no merging (fragment_gap < 0) the piece is an object of its own.
  ObjectOptions apart;
  apart.fragment_gap = -1;
  EXPECT_EQ(find_objects(image, apart).objects.size(), 3u);
  // A gap of 1 is too small for this piece.
  ObjectOptions one;
  one.fragment_gap = 1;
  EXPECT_EQ(find_objects(image, one).fragments_merged, 0);
}

TEST(Fragments, NeighboursOfSimilarSizeAreNeverMerged) {
  // Two balls two voxels apart (as UroCell's neighbouring lysosomes): no component dominates, both are objects.
  LabelImage image = empty_image(48);
  paint_ball(image, {14, 24, 24}, 9, 1);
  paint_ball(image, {34, 24, 24}, 8, 1);
  const ObjectSet set = find_objects(image);
  EXPECT_EQ(set.fragments_merged, 0);
  EXPECT_EQ(set.objects.size(), 2u);
}

}  // namespace
}  // namespace wish::volume
