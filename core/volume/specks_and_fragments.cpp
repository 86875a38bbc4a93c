#include "core/volume/specks_and_fragments.hpp"

#include <algorithm>
#include <cmath>

namespace wish::volume {

SpeckRule speck_rule(const std::vector<std::int64_t>& voxel_counts) {
  SpeckRule rule;
  if (voxel_counts.empty()) return rule;
  const std::int64_t largest = *std::max_element(voxel_counts.begin(), voxel_counts.end());
  std::vector<std::int64_t> sizable;
  for (const std::int64_t n : voxel_counts)
    if (static_cast<double>(n) >= kTypicalShareOfLargest * static_cast<double>(largest)) sizable.push_back(n);
  std::nth_element(sizable.begin(), sizable.begin() + static_cast<std::ptrdiff_t>(sizable.size() / 2), sizable.end());
  rule.typical_voxels = sizable[sizable.size() / 2];
  rule.below = std::max<std::int64_t>(kSpeckFloorVoxels,
                                      static_cast<std::int64_t>(std::ceil(kSpeckShare * static_cast<double>(rule.typical_voxels))));
  return rule;
}

std::vector<int> gaps_to_component(const std::array<std::int64_t, 3>& dims, const std::vector<std::uint32_t>& ids,
                                   const std::vector<std::array<std::int64_t, 3>>& box_min,
                                   const std::vector<std::array<std::int64_t, 3>>& box_max, std::uint32_t main, int max_gap) {
  const std::size_t n = box_min.size();
  std::vector<int> gap(n, -1);
  if (max_gap < 0 || main == 0 || main > n) return gap;
  const std::int64_t reach = max_gap + 1;  // Chebyshev distance of the farthest voxel that still counts
  const auto& main_lo = box_min[main - 1];
  const auto& main_hi = box_max[main - 1];
  const std::int64_t nx = dims[0], ny = dims[1], nz = dims[2];
  auto id_at = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    return ids[static_cast<std::size_t>(x + nx * (y + ny * z))];
  };
  for (std::size_t c = 0; c < n; ++c) {
    const std::uint32_t cid = static_cast<std::uint32_t>(c + 1);
    if (cid == main) continue;
    bool near = true;  // the boxes, grown by the reach, overlap
    for (int k = 0; k < 3; ++k) near = near && box_min[c][k] - reach <= main_hi[k] && box_max[c][k] + reach >= main_lo[k];
    if (!near) continue;
    std::int64_t best = reach + 1;
    for (std::int64_t z = box_min[c][2]; z <= box_max[c][2] && best > 1; ++z)
      for (std::int64_t y = box_min[c][1]; y <= box_max[c][1] && best > 1; ++y)
        for (std::int64_t x = box_min[c][0]; x <= box_max[c][0] && best > 1; ++x) {
          if (id_at(x, y, z) != cid) continue;
          // Only the component's boundary voxels can be nearest to another component.
          const bool inner = x > 0 && y > 0 && z > 0 && x + 1 < nx && y + 1 < ny && z + 1 < nz &&
                             id_at(x - 1, y, z) == cid && id_at(x + 1, y, z) == cid && id_at(x, y - 1, z) == cid &&
                             id_at(x, y + 1, z) == cid && id_at(x, y, z - 1) == cid && id_at(x, y, z + 1) == cid;
          if (inner) continue;
          const std::int64_t r = best - 1;  // look only for something nearer than the best so far
          for (std::int64_t c2 = std::max<std::int64_t>(0, z - r); c2 <= std::min(nz - 1, z + r); ++c2)
            for (std::int64_t b = std::max<std::int64_t>(0, y - r); b <= std::min(ny - 1, y + r); ++b)
              for (std::int64_t a = std::max<std::int64_t>(0, x - r); a <= std::min(nx - 1, x + r); ++a)
                if (id_at(a, b, c2) == main)
                  best = std::min(best, std::max({std::abs(a - x), std::abs(b - y), std::abs(c2 - z)}));
        }
    if (best <= reach) gap[c] = static_cast<int>(best - 1);
  }
  return gap;
}

}  // namespace wish::volume
