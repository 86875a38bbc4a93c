// What auto mode takes a volume for (core/volume/input_kind.hpp), on analytic shapes whose right objects are known:
//   * a sphere whose boundary voxels hold a linear partial-volume ramp (255 · clamp(R + 0.5 − d)) is a soft mask,
//     and thresholding at half its maximum gives exactly the voxels with d ≤ R (the clean voxelised sphere);
//   * the same sphere trilinearly upsampled (grey edges of a resize) gives one object of the clean sphere's volume
//     within its boundary shell and centroid within a voxel, read through NIfTI as a user's file is;
//   * a float32 probability map (a logistic of the signed distance, written to NIfTI and read back) is a
//     probability map thresholded at 0.5: exactly d ≤ R again; an 8-bit one with wide ramps too;
//   * labels stay labels (touching boxes, no warning) and a plain mask is a mask; a soft mask forced to labels, or
//     grey shells read as labels, warn with the option that helps; bad thresholds are refused with the reason.
#include <gtest/gtest.h>

#include <cmath>

#include "core/common/errors.hpp"
#include "core/io/volume_io.hpp"
#include "core/volume/input_kind.hpp"
#include "core/volume/label_objects.hpp"

namespace wish::volume {
namespace {

constexpr int kN = 40;
const Eigen::Vector3d kCentre(19.3, 20.1, 18.7);  // off the grid: no voxel centre at distance exactly R
constexpr double kR = 11.0;

LabelImage grid(int n = kN) {
  LabelImage image;
  image.dims = {n, n, n};
  image.labels.assign(static_cast<std::size_t>(image.voxel_count()), 0);
  return image;
}

double distance(std::int64_t x, std::int64_t y, std::int64_t z) {
  return (Eigen::Vector3d(static_cast<double>(x), static_cast<double>(y), static_cast<double>(z)) - kCentre).norm();
}

template <typename F>
LabelImage fill(F value, int n = kN) {
  LabelImage image = grid(n);
  for (std::int64_t z = 0; z < n; ++z)
    for (std::int64_t y = 0; y < n; ++y)
      for (std::int64_t x = 0; x < n; ++x) image.labels[image.index(x, y, z)] = value(x, y, z);
  return image;
}

LabelImage clean_sphere() { return fill([](auto x, auto y, auto z) -> std::uint32_t { return distance(x, y, z) <= kR ? 1 : 0; }); }

// The object's voxels as a 0/1 image, for exact comparison with the clean sphere.
std::vector<std::uint32_t> object_voxels(const LabelImage& image, const ObjectSet& set, std::uint32_t id) {
  std::vector<std::uint32_t> out(image.labels.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = set.id_at(image, i) == id;
  return out;
}

TEST(InputKind, SphereWithLinearGreyEdgesIsASoftMaskThresholdedToTheCleanSphere) {
  const LabelImage soft = fill([](auto x, auto y, auto z) {
    return static_cast<std::uint32_t>(std::lround(255 * std::clamp(kR + 0.5 - distance(x, y, z), 0.0, 1.0)));
  });
  const ObjectSet set = find_objects(soft);  // the default: auto
  EXPECT_EQ(set.input.kind, InputKind::SoftMask) << set.input.why;
  EXPECT_EQ(set.mode, ObjectMode::Components);
  ASSERT_TRUE(set.input.threshold.has_value());
  EXPECT_EQ(*set.input.threshold, 127.5);
  EXPECT_TRUE(set.input.warnings.empty());
  ASSERT_EQ(set.objects.size(), 1u);
  EXPECT_EQ(object_voxels(soft, set, set.objects[0].id), clean_sphere().labels);
  // The same file read as labels (the old auto rule) is dozens of slivers, and says so.
  ObjectOptions as_labels;
  as_labels.mode = ObjectMode::Labels;
  const ObjectSet wrong = find_objects(soft, as_labels);
  EXPECT_GT(wrong.found, 40);  // distinct values: objects, before the small ones are dropped as specks
  ASSERT_EQ(wrong.input.warnings.size(), 1u);
  EXPECT_NE(wrong.input.warnings[0].find("--threshold"), std::string::npos) << wrong.input.warnings[0];
}

// Trilinear interpolation of the clean sphere (0/255) at a grid `factor` times finer (corners aligned), as a resize
// of a mask leaves it, written as uint8 NIfTI and read back.
TEST(InputKind, TrilinearlyUpsampledSphereGivesTheCleanSphereWithinItsBoundaryShell) {
  const LabelImage clean = clean_sphere();
  const int m = 2 * kN - 1;  // factor 2 with aligned corners: voxel j samples the clean grid at j / 2
  LabelImage soft = grid(m);
  soft.spacing = Eigen::Vector3d::Constant(0.5);
  auto at = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    return clean.labels[clean.index(std::min<std::int64_t>(x, kN - 1), std::min<std::int64_t>(y, kN - 1),
                                    std::min<std::int64_t>(z, kN - 1))] * 255.0;
  };
  for (std::int64_t z = 0; z < m; ++z)
    for (std::int64_t y = 0; y < m; ++y)
      for (std::int64_t x = 0; x < m; ++x) {
        const std::int64_t i = x / 2, j = y / 2, k = z / 2;
        const double fx = 0.5 * (x % 2), fy = 0.5 * (y % 2), fz = 0.5 * (z % 2);
        double v = 0;
        for (int c = 0; c < 8; ++c) {
          const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
          v += (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy) * (dz ? fz : 1 - fz) * at(i + dx, j + dy, k + dz);
        }
        soft.labels[soft.index(x, y, z)] = static_cast<std::uint32_t>(std::lround(v));
      }
  const VolumeReadResult read = read_volume(write_nifti(soft, "uint8", true));
  const ObjectSet set = find_objects(read.image);
  EXPECT_EQ(set.input.kind, InputKind::SoftMask) << set.input.why;
  ASSERT_EQ(set.objects.size(), 1u);
  const ObjectSet reference = find_objects(clean);
  ASSERT_EQ(reference.objects.size(), 1u);
  // Boundary shell of the clean sphere: its voxels with a background 6-neighbour, in clean voxel volumes (1).
  std::int64_t shell = 0;
  for (std::int64_t z = 1; z + 1 < kN; ++z)
    for (std::int64_t y = 1; y + 1 < kN; ++y)
      for (std::int64_t x = 1; x + 1 < kN; ++x)
        if (clean.at(x, y, z) && (!clean.at(x - 1, y, z) || !clean.at(x + 1, y, z) || !clean.at(x, y - 1, z) ||
                                  !clean.at(x, y + 1, z) || !clean.at(x, y, z - 1) || !clean.at(x, y, z + 1)))
          ++shell;
  const double volume = static_cast<double>(set.objects[0].voxel_count) * 0.125;  // fine voxels are 1/8 of a clean one
  EXPECT_NEAR(volume, static_cast<double>(reference.objects[0].voxel_count), static_cast<double>(shell));
  EXPECT_LT((set.objects[0].centroid - reference.objects[0].centroid).norm(), 1.0);
  std::printf("trilinear x2: %.1f clean-voxel volumes against %lld (shell %lld), centroid off by %.3f\n", volume,
              static_cast<long long>(reference.objects[0].voxel_count), static_cast<long long>(shell),
              (set.objects[0].centroid - reference.objects[0].centroid).norm());
}

double logistic(double t) { return 1 / (1 + std::exp(-t)); }

TEST(InputKind, FloatProbabilityMapIsThresholdedAtOneHalfToTheCleanSphere) {
  LabelImage map = fill([](auto x, auto y, auto z) {
    return static_cast<std::uint32_t>(std::lround(logistic((kR - distance(x, y, z)) / 1.5) * LabelImage::kProbabilityScale));
  });
  map.probability_scale = LabelImage::kProbabilityScale;
  for (const char* type : {"float32", "float64"}) {
    const VolumeReadResult read = read_volume(write_nifti(map, type));
    EXPECT_EQ(read.image.probability_scale, LabelImage::kProbabilityScale) << type;
    const ObjectSet set = find_objects(read.image);
    EXPECT_EQ(set.input.kind, InputKind::ProbabilityMap) << set.input.why;
    ASSERT_TRUE(set.input.threshold.has_value());
    EXPECT_EQ(*set.input.threshold, 0.5);
    ASSERT_EQ(set.objects.size(), 1u) << type;
    EXPECT_EQ(object_voxels(read.image, set, set.objects[0].id), clean_sphere().labels) << type;
    // A caller's threshold is in probabilities: 0.9 keeps d ≤ R − 1.5 ln 9.
    ObjectOptions high;
    high.threshold = 0.9;
    const ObjectSet inner = find_objects(read.image, high);
    ASSERT_EQ(inner.objects.size(), 1u);
    const double r = kR - 1.5 * std::log(9.0);
    const LabelImage expected = fill([r](auto x, auto y, auto z) -> std::uint32_t { return distance(x, y, z) <= r ? 1 : 0; });
    EXPECT_EQ(object_voxels(read.image, inner, inner.objects[0].id), expected.labels);
  }
}

TEST(InputKind, EightBitProbabilityMapWithWideRampsIsAProbabilityMap) {
  // Ramps over about ±7 voxels: most grey voxels lie far from the 255 core, so it is not a soft mask.
  const LabelImage map = fill([](auto x, auto y, auto z) {
    return static_cast<std::uint32_t>(std::lround(255 * logistic((kR + 3 - distance(x, y, z)) / 1.2)));
  }, 56);
  const ObjectSet set = find_objects(map);
  EXPECT_EQ(set.input.kind, InputKind::ProbabilityMap) << set.input.why;
  ASSERT_TRUE(set.input.threshold.has_value());
  EXPECT_EQ(*set.input.threshold, 127.5);
  ASSERT_EQ(set.objects.size(), 1u);
  // 255 · logistic(t) rounds to 128 or more exactly when it is ≥ 127.5, i.e. t ≥ 0: d ≤ R + 3.
  std::int64_t inside = 0;
  for (std::int64_t z = 0; z < 56; ++z)
    for (std::int64_t y = 0; y < 56; ++y)
      for (std::int64_t x = 0; x < 56; ++x) inside += distance(x, y, z) <= kR + 3;
  EXPECT_EQ(set.objects[0].voxel_count, inside);
}

TEST(InputKind, LabelsStayLabelsAndAMaskIsAMask) {
  // Three touching boxes, labels 1, 2, 3 (the largest label is not the most frequent value).
  const LabelImage boxes = fill([](auto x, auto y, auto z) -> std::uint32_t {
    if (y < 10 || y >= 30 || z < 10 || z >= 30) return 0;
    return x >= 5 && x < 25 ? 1 : x >= 25 && x < 30 ? 3 : x >= 30 && x < 35 ? 2 : 0;
  });
  const ObjectSet set = find_objects(boxes);
  EXPECT_EQ(set.input.kind, InputKind::Labels) << set.input.why;
  EXPECT_EQ(set.mode, ObjectMode::Labels);
  EXPECT_FALSE(set.input.threshold.has_value());
  EXPECT_TRUE(set.input.warnings.empty());
  EXPECT_EQ(set.objects.size(), 3u);
  const ObjectSet mask = find_objects(clean_sphere());
  EXPECT_EQ(mask.input.kind, InputKind::Mask);
  EXPECT_EQ(mask.mode, ObjectMode::Components);
  EXPECT_FALSE(mask.input.threshold.has_value());
}

TEST(InputKind, GreyShellsReadAsLabelsWarnWithTheOptionThatHelps) {
  // Concentric one-voxel shells of values 1, 2, 3 around a small core of 4: the core is the largest value but not
  // the most frequent, so this is not recognised as a soft mask; the shells are slivers lying against each other.
  const LabelImage shells = fill([](auto x, auto y, auto z) -> std::uint32_t {
    const double d = distance(x, y, z);
    return d <= 3 ? 4 : d <= 4 ? 3 : d <= 5 ? 2 : d <= 6 ? 1 : 0;
  });
  const ObjectSet set = find_objects(shells);
  EXPECT_EQ(set.input.kind, InputKind::Labels);
  ASSERT_EQ(set.input.warnings.size(), 1u);
  EXPECT_NE(set.input.warnings[0].find("3 of the 4 labels are thin boundary slivers"), std::string::npos)
      << set.input.warnings[0];
  EXPECT_NE(set.input.warnings[0].find("--objects components --threshold"), std::string::npos);
  // Following the advice gives the one object.
  ObjectOptions advice;
  advice.mode = ObjectMode::Components;
  advice.threshold = 1;
  EXPECT_EQ(find_objects(shells, advice).objects.size(), 1u);
}

TEST(InputKind, ThresholdsAreCheckedAndTheCallersWins) {
  const LabelImage soft = fill([](auto x, auto y, auto z) {
    return static_cast<std::uint32_t>(std::lround(255 * std::clamp(kR + 0.5 - distance(x, y, z), 0.0, 1.0)));
  });
  auto code = [&](ObjectMode mode, double t) {
    ObjectOptions o;
    o.mode = mode;
    o.threshold = t;
    try {
      find_objects(soft, o);
    } catch (const WishError& e) {
      return e.code();
    }
    return std::string("none");
  };
  EXPECT_EQ(code(ObjectMode::Auto, 0), "invalid_parameter");
  EXPECT_EQ(code(ObjectMode::Auto, -3), "invalid_parameter");
  EXPECT_EQ(code(ObjectMode::Auto, std::nan("")), "invalid_parameter");
  EXPECT_EQ(code(ObjectMode::Labels, 100), "invalid_parameter");
  EXPECT_EQ(code(ObjectMode::Components, 100), "none");
  // threshold 1: every non-zero voxel, i.e. d ≤ R + 0.5 minus the voxels rounded to 0.
  ObjectOptions low;
  low.threshold = 1;
  const ObjectSet set = find_objects(soft, low);
  EXPECT_EQ(set.input.kind, InputKind::SoftMask);
  EXPECT_EQ(*set.input.threshold, 1.0);
  EXPECT_NE(set.input.why.find("set by the caller"), std::string::npos);
  std::int64_t nonzero = 0;
  for (auto v : soft.labels) nonzero += v != 0;
  EXPECT_EQ(set.objects[0].voxel_count, nonzero);
  // A float probability map takes thresholds in (0, 1] and is not labels.
  LabelImage map = soft;
  map.probability_scale = LabelImage::kProbabilityScale;
  ObjectOptions above_one;
  above_one.threshold = 2;
  EXPECT_THROW(find_objects(map, above_one), InvalidInputError);
  ObjectOptions labels;
  labels.mode = ObjectMode::Labels;
  EXPECT_THROW(find_objects(map, labels), InvalidInputError);
}

}  // namespace
}  // namespace wish::volume
