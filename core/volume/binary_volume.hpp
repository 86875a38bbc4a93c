#pragma once
// A binary volume (one object of a segmentation, or a voxelised demo shape; docs/design/classification.md: demo meshes are made
// "the way segmentation output is"), and the clean-up that makes its surface one closed genus-0-candidate sheet:
// keep the largest foreground component and fill enclosed background cavities.
// Connectivity is the 14-neighbourhood of the Kuhn (Freudenthal) triangulation used by marching_tetrahedra:
// grid points are joined along the offsets {100, 010, 001, 110, 101, 011, 111} and their negatives. With the same
// connectivity on both sides, one foreground and one background component give exactly one surface component.

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace wish::volume {

struct BinaryVolume {
  std::array<int, 3> dims{0, 0, 0};      // nx, ny, nz
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // world position of voxel (0, 0, 0)
  Eigen::Vector3d spacing = Eigen::Vector3d::Ones();  // voxel size along x, y, z (physical units)
  std::vector<std::uint8_t> labels;      // 1 inside, 0 outside; x fastest

  std::size_t index(int x, int y, int z) const {
    return static_cast<std::size_t>(x) + static_cast<std::size_t>(dims[0]) * (y + static_cast<std::size_t>(dims[1]) * z);
  }
  std::uint8_t at(int x, int y, int z) const { return labels[index(x, y, z)]; }
};

// The 7 positive Kuhn-triangulation offsets (the 14-neighbourhood is these and their negatives).
const std::array<std::array<int, 3>, 7>& kuhn_offsets();

// The 14-connected components of the voxels of value `value`: `id` gets a component number per voxel (-1 for the
// other value); returns the components' sizes, numbered in scan order (z, y, x).
std::vector<std::size_t> components(const BinaryVolume& volume, std::uint8_t value, std::vector<int>& id);
// Per component of `id` (as components() numbers them, `count` of them): whether it has a voxel on the border layer.
std::vector<bool> touching_border(const BinaryVolume& volume, const std::vector<int>& id, std::size_t count);

// Keeps only the largest 14-connected foreground component; returns the number of components found.
int keep_largest_component(BinaryVolume& volume);
// Sets background components that do not touch the volume border to foreground; returns how many were filled.
int fill_cavities(BinaryVolume& volume);
// Clears the outermost layer so the surface is closed inside the grid.
void clear_border(BinaryVolume& volume);

}  // namespace wish::volume
