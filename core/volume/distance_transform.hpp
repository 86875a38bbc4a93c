#pragma once
// Exact squared Euclidean distance transform of a binary volume in physical units (anisotropic spacing honoured):
// for every voxel, the squared distance from its centre to the nearest voxel centre of value `target` (0 for a voxel
// of that value; +infinity when the volume has none). Separable, one pass per axis, each the lower envelope of
// parabolas of Felzenszwalb & Huttenlocher (2012), linear in the voxel count.

#include <cstdint>
#include <vector>

#include "core/volume/binary_volume.hpp"

namespace wish::volume {

std::vector<double> squared_distance_to(const BinaryVolume& volume, std::uint8_t target);

}  // namespace wish::volume
