#pragma once
// A 3-D label image as a segmentation leaves it: one unsigned integer per voxel, 0 = background, any other value
// names an object (or, for a binary mask, marks foreground whose 6-connected components are the objects).
// Conventions: x fastest, then y, then z; voxel (i, j, k) has its centre at spacing ⊙ (i, j, k) in `unit`
// (so the first voxel's centre is the origin and meshes come out in physical units).
// A probability map stored as floats (values in [0, 1], not all integers) is held in the same integers as fixed
// point: `labels` = round(p × probability_scale). 2^24 keeps a float32 probability exactly from 0.5 to 1 (its
// mantissa has 24 bits there) and to 6e-8 below, far finer than any threshold a caller sets.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace wish::volume {

struct LabelImage {
  std::array<std::int64_t, 3> dims{0, 0, 0};            // nx, ny, nz
  Eigen::Vector3d spacing = Eigen::Vector3d::Ones();     // voxel size along x, y, z, in `unit`
  std::string unit;                                       // "nm", "um", "mm", ... ; empty when unknown
  std::vector<std::uint32_t> labels;                     // nx * ny * nz values
  std::uint32_t probability_scale = 0;                   // > 0: a probability map, labels = round(p × scale)

  static constexpr std::uint32_t kProbabilityScale = 1u << 24;

  std::int64_t voxel_count() const { return dims[0] * dims[1] * dims[2]; }
  std::size_t index(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return static_cast<std::size_t>(x + dims[0] * (y + dims[1] * z));
  }
  std::uint32_t at(std::int64_t x, std::int64_t y, std::int64_t z) const { return labels[index(x, y, z)]; }
};

}  // namespace wish::volume
