// Masks as labs save them, made from the UroCell objects (../shared/data/urocell, skipped when absent; suite named
// Slow* so the sanitizer run skips it), each read in the default auto mode against the clean volume's objects:
//   * linear resampling (a resize by 1.25 with trilinear interpolation of the 0/255 mask: grey edges) is a soft
//     mask, thresholded at 127.5;
//   * a Gaussian-blurred probability map (σ = 0.7 voxel, 8-bit) is a probability map, thresholded at 127.5;
//   * nearest-neighbour resampling of the instance labels (the same resize) stays labels, with no warning.
// "Same objects": every complete clean object (≥ 500 voxels, not touching the border) has one object of the mask
// whose centroid lies within one clean voxel, with a volume within the clean object's boundary shell (its voxels
// with a background 6-neighbour), and every complete object of the mask above 600 clean voxels is one of those.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>

#include "core/io/volume_io.hpp"
#include "core/volume/label_objects.hpp"
#include "tests/testing/test_data.hpp"

namespace wish::volume {
namespace {

namespace fs = std::filesystem;

constexpr double kScale = 1.25;
constexpr std::int64_t kMinVoxels = 500;

std::optional<LabelImage> urocell(const char* sub) {
  const auto data = wish::testing::shared_data_dir();
  if (!data) return std::nullopt;
  const fs::path f = *data / "urocell" / sub / "fib1-0-0-0.nii.gz";
  if (!fs::exists(f)) return std::nullopt;
  LabelImage image = read_volume_file(f).image;
  image.spacing = Eigen::Vector3d::Ones();  // clean voxel units throughout
  return image;
}

LabelImage binary_255(const LabelImage& labels) {
  LabelImage mask = labels;
  for (auto& v : mask.labels) v = v ? 255 : 0;
  return mask;
}

// Resize with aligned corners: m = round((n − 1) s) + 1 voxels per axis, voxel j samples the input at
// j (n − 1) / (m − 1). Trilinear (rounded to integers) or nearest neighbour.
LabelImage resize(const LabelImage& in, bool linear) {
  LabelImage out;
  std::vector<std::int64_t> i0[3];
  std::vector<double> frac[3];
  for (int k = 0; k < 3; ++k) {
    const std::int64_t n = in.dims[k];
    const std::int64_t m = std::llround(static_cast<double>(n - 1) * kScale) + 1;
    out.dims[k] = m;
    out.spacing(k) = static_cast<double>(n - 1) / static_cast<double>(m - 1);
    for (std::int64_t j = 0; j < m; ++j) {
      const double p = static_cast<double>(j) * out.spacing(k);
      const std::int64_t lo = std::min<std::int64_t>(static_cast<std::int64_t>(std::floor(p)), n - 2);
      i0[k].push_back(lo);
      frac[k].push_back(p - static_cast<double>(lo));
    }
  }
  out.labels.resize(static_cast<std::size_t>(out.voxel_count()));
  std::size_t i = 0;
  for (std::int64_t z = 0; z < out.dims[2]; ++z)
    for (std::int64_t y = 0; y < out.dims[1]; ++y)
      for (std::int64_t x = 0; x < out.dims[0]; ++x, ++i) {
        const std::int64_t p[3] = {x, y, z};
        if (!linear) {
          std::int64_t q[3];
          for (int k = 0; k < 3; ++k) q[k] = i0[k][static_cast<std::size_t>(p[k])] + (frac[k][static_cast<std::size_t>(p[k])] >= 0.5);
          out.labels[i] = in.at(q[0], q[1], q[2]);
          continue;
        }
        double v = 0;
        for (int c = 0; c < 8; ++c) {
          double w = 1;
          std::int64_t q[3];
          for (int k = 0; k < 3; ++k) {
            const int d = (c >> k) & 1;
            const double f = frac[k][static_cast<std::size_t>(p[k])];
            w *= d ? f : 1 - f;
            q[k] = i0[k][static_cast<std::size_t>(p[k])] + d;
          }
          if (w > 0) v += w * in.at(q[0], q[1], q[2]);
        }
        out.labels[i] = static_cast<std::uint32_t>(std::lround(v));
      }
  return out;
}

// 255 × (the 0/1 mask blurred by a Gaussian of σ voxels, truncated at 4σ, border voxels repeated), rounded: an 8-bit
// probability map.
LabelImage blurred(const LabelImage& labels, double sigma) {
  std::vector<double> f(labels.labels.size());
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = labels.labels[i] ? 1.0 : 0.0;
  const int r = static_cast<int>(std::ceil(4 * sigma));
  std::vector<double> kernel(static_cast<std::size_t>(2 * r + 1));
  double sum = 0;
  for (int d = -r; d <= r; ++d) sum += kernel[static_cast<std::size_t>(d + r)] = std::exp(-0.5 * d * d / (sigma * sigma));
  for (auto& k : kernel) k /= sum;
  const std::int64_t stride[3] = {1, labels.dims[0], labels.dims[0] * labels.dims[1]};
  std::vector<double> line;
  for (int axis = 0; axis < 3; ++axis) {
    const std::int64_t n = labels.dims[axis], st = stride[axis];
    line.resize(static_cast<std::size_t>(n));
    for (std::int64_t start = 0; start < static_cast<std::int64_t>(f.size()); ++start) {
      if ((start / st) % n != 0) continue;
      for (std::int64_t k = 0; k < n; ++k) line[static_cast<std::size_t>(k)] = f[static_cast<std::size_t>(start + k * st)];
      for (std::int64_t k = 0; k < n; ++k) {
        double acc = 0;
        for (int d = -r; d <= r; ++d)  // the border voxel repeated outside (zeros would shrink objects at the border)
          acc += kernel[static_cast<std::size_t>(d + r)] * line[static_cast<std::size_t>(std::clamp<std::int64_t>(k + d, 0, n - 1))];
        f[static_cast<std::size_t>(start + k * st)] = acc;
      }
    }
  }
  LabelImage out = labels;
  for (std::size_t i = 0; i < f.size(); ++i) out.labels[i] = static_cast<std::uint32_t>(std::lround(255 * f[i]));
  return out;
}

// Boundary shell per object: its voxels with a 6-neighbour of another id (background included).
std::map<std::uint32_t, std::int64_t> shells(const LabelImage& image, const ObjectSet& set) {
  std::map<std::uint32_t, std::int64_t> out;
  const std::int64_t nx = image.dims[0], ny = image.dims[1], nz = image.dims[2];
  for (std::int64_t z = 1; z + 1 < nz; ++z)
    for (std::int64_t y = 1; y + 1 < ny; ++y)
      for (std::int64_t x = 1; x + 1 < nx; ++x) {
        const std::size_t i = image.index(x, y, z);
        const std::uint32_t id = set.id_at(image, i);
        if (id == 0) continue;
        const std::size_t n[6] = {i - 1, i + 1, i - static_cast<std::size_t>(nx), i + static_cast<std::size_t>(nx),
                                  i - static_cast<std::size_t>(nx * ny), i + static_cast<std::size_t>(nx * ny)};
        for (std::size_t j : n)
          if (set.id_at(image, j) != id) {
            ++out[id];
            break;
          }
      }
  return out;
}

ObjectSet complete_objects(const LabelImage& image, double voxel_volume) {
  ObjectOptions o;
  o.drop_truncated = true;
  o.min_voxels = static_cast<std::int64_t>(std::floor(0.5 * kMinVoxels / voxel_volume));  // the band is checked below
  return find_objects(image, o);
}

struct Match {
  int clean = 0, matched = 0, extra = 0;
  double worst_centroid = 0, worst_volume_share_of_shell = 0;
};

// Same objects within a voxel (the rule at the top of this file); `by_label`: match by label id, else by centroid.
Match compare(const LabelImage& clean, const LabelImage& other, bool by_label) {
  const ObjectSet a = complete_objects(clean, 1.0);
  const ObjectSet b = complete_objects(other, other.spacing.prod());
  const auto shell = shells(clean, a);
  Match m;
  std::vector<bool> used(b.objects.size(), false);
  for (const VolumeObject& o : a.objects) {
    if (o.voxel_count < kMinVoxels) continue;
    ++m.clean;
    std::size_t best = b.objects.size();
    double best_d = 1e300;
    for (std::size_t k = 0; k < b.objects.size(); ++k) {
      if (by_label && b.objects[k].id != o.id) continue;
      const double d = (b.objects[k].centroid - o.centroid).norm();
      if (d < best_d) best_d = d, best = k;
    }
    if (best == b.objects.size()) {
      ADD_FAILURE() << "clean object " << o.id << " (" << o.voxel_count << " voxels) has no counterpart";
      continue;
    }
    const double volume = static_cast<double>(b.objects[best].voxel_count) * other.spacing.prod();
    const double dv = std::abs(volume - static_cast<double>(o.voxel_count));
    EXPECT_LT(best_d, 1.0) << "object " << o.id;
    EXPECT_LE(dv, static_cast<double>(shell.at(o.id))) << "object " << o.id << ": " << volume << " against " << o.voxel_count;
    EXPECT_FALSE(used[best]) << "two clean objects matched one";
    used[best] = true;
    ++m.matched;
    m.worst_centroid = std::max(m.worst_centroid, best_d);
    m.worst_volume_share_of_shell = std::max(m.worst_volume_share_of_shell, dv / static_cast<double>(shell.at(o.id)));
  }
  for (std::size_t k = 0; k < b.objects.size(); ++k)
    if (!used[k] && static_cast<double>(b.objects[k].voxel_count) * other.spacing.prod() > 1.2 * kMinVoxels) {
      ++m.extra;
      ADD_FAILURE() << "object " << b.objects[k].id << " of the mask (" << b.objects[k].voxel_count
                    << " voxels) is none of the clean objects";
    }
  return m;
}

void report(const char* what, const ObjectSet& set, const Match& m) {
  std::printf("%s: input %s, threshold %s; %d complete clean objects, %d matched, %d extra; worst centroid %.3f voxel, "
              "worst |dV| %.0f %% of the boundary shell\n  why: %s\n",
              what, to_string(set.input.kind), set.input.threshold ? std::to_string(*set.input.threshold).c_str() : "none",
              m.clean, m.matched, m.extra, m.worst_centroid, 100 * m.worst_volume_share_of_shell, set.input.why.c_str());
}

class SlowUroCellMasks : public ::testing::TestWithParam<const char*> {};

TEST_P(SlowUroCellMasks, LinearlyResampledMaskIsASoftMaskWithTheCleanObjects) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const auto labels = urocell(GetParam());
  if (!labels) GTEST_SKIP() << "urocell absent";
  const LabelImage clean = binary_255(*labels);
  const LabelImage soft = resize(clean, /*linear=*/true);
  const ObjectSet set = find_objects(soft);
  EXPECT_EQ(set.input.kind, InputKind::SoftMask) << set.input.why;
  ASSERT_TRUE(set.input.threshold.has_value());
  EXPECT_EQ(*set.input.threshold, 127.5);
  const Match m = compare(clean, soft, false);
  EXPECT_GT(m.clean, 0);
  report(GetParam(), set, m);
}

TEST_P(SlowUroCellMasks, BlurredProbabilityMapIsThresholdedToTheCleanObjects) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const auto labels = urocell(GetParam());
  if (!labels) GTEST_SKIP() << "urocell absent";
  const LabelImage map = blurred(*labels, 0.7);
  const ObjectSet set = find_objects(map);
  EXPECT_EQ(set.input.kind, InputKind::ProbabilityMap) << set.input.why;
  const Match m = compare(binary_255(*labels), map, false);
  EXPECT_GT(m.clean, 0);
  report(GetParam(), set, m);
}

TEST_P(SlowUroCellMasks, NearestNeighbourResampledLabelsStayLabels) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const auto labels = urocell(GetParam());
  if (!labels) GTEST_SKIP() << "urocell absent";
  const LabelImage nn = resize(*labels, /*linear=*/false);
  const ObjectSet set = find_objects(nn);
  const ObjectSet original = find_objects(*labels);
  EXPECT_EQ(set.input.kind, original.input.kind) << set.input.why;  // instances stay labels, a binary mask a mask
  EXPECT_NE(set.input.kind, InputKind::SoftMask);
  EXPECT_NE(set.input.kind, InputKind::ProbabilityMap);
  EXPECT_TRUE(set.input.warnings.empty());
  const Match m = compare(*labels, nn, original.input.kind == InputKind::Labels);
  EXPECT_GT(m.clean, 0);
  report(GetParam(), set, m);
}

INSTANTIATE_TEST_SUITE_P(UroCell, SlowUroCellMasks, ::testing::Values("mito/instance", "lyso/binary"),
                         [](const auto& info) { return std::string(info.param).substr(0, 4); });

}  // namespace
}  // namespace wish::volume
