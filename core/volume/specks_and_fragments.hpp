#pragma once
// The objects a lab means, out of the pieces a threshold or a segmentation leaves (issue 39):
//   * a speck is not an object: an object of fewer than kSpeckFloorVoxels voxels, or of fewer than kSpeckShare of
//     the volume's typical object (the median voxel count of the objects holding at least kTypicalShareOfLargest of
//     the largest one's voxels: specks do not drag it down, and in a one-object mask it is that object). Specks are
//     dropped, counted and listed with their reason; `min_voxels` replaces the rule with a fixed count.
//   * a fragment is part of an object: in a mask whose largest component holds at least kDominantShare of the
//     foreground (one object, broken by a resampling or a threshold), every other component that lies within
//     `fragment_gap` background voxels of it (Chebyshev distance gap + 1, 26-neighbourhood steps) is one of its
//     pieces. Listed with the object; the object's voxel count, centroid and box include them.
// Why these figures (docs/accuracy.md, "Specks and fragments"): the 14 UroCell volumes' objects span 4 to 101,456
// voxels; the rule drops only a 4-voxel fv label inside fib1-4-3-0 and a 10-voxel sliver of a vesicle on the border
// of fib1-3-3-0 (the next smallest, 58 voxels, is 2.0 times the rule's bound there). The real neighbouring
// lysosomes of UroCell's masks, 1 to 5 voxels apart, are never merged: no mask there has one dominant component
// with neighbours (the largest holds 17-44 %, or 88 % with no other piece within 5 voxels).

#include <array>
#include <cstdint>
#include <vector>

namespace wish::volume {

inline constexpr std::int64_t kSpeckFloorVoxels = 8;   // fewer: never an object by default (under a 2 x 2 x 2 cube)
inline constexpr double kSpeckShare = 0.005;           // of the typical object's voxels
inline constexpr double kTypicalShareOfLargest = 0.10;
inline constexpr double kDominantShare = 0.75;
inline constexpr int kDefaultFragmentGap = 3;

struct SpeckRule {
  std::int64_t typical_voxels = 0;  // 0: no objects
  std::int64_t below = 0;           // objects with fewer voxels are specks
};

SpeckRule speck_rule(const std::vector<std::int64_t>& voxel_counts);

// For components numbered 1..n (`component_ids`: one per voxel of a dims[0] x dims[1] x dims[2] grid, x fastest; 0
// background) and the box of each (`box_min`, `box_max`, voxel indices, inclusive): the background gap between each
// component and component `main` (0 when they touch diagonally), or -1 when it is more than `max_gap` (and for
// `main` itself).
std::vector<int> gaps_to_component(const std::array<std::int64_t, 3>& dims, const std::vector<std::uint32_t>& component_ids,
                                   const std::vector<std::array<std::int64_t, 3>>& box_min,
                                   const std::vector<std::array<std::int64_t, 3>>& box_max, std::uint32_t main, int max_gap);

}  // namespace wish::volume
