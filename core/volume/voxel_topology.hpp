#pragma once
// The topology of a binary volume's foreground, in the triangulation the surface is extracted on: the Kuhn
// (Freudenthal) triangulation of marching_tetrahedra.hpp, whose edges are the 14-neighbourhood of binary_volume.hpp.
// The foreground is the full subcomplex on the foreground grid points (every simplex whose vertices are all
// foreground); the marching-tetrahedra surface is the boundary of its regular neighbourhood, so the surface's genus
// is the foreground's number of handles when the foreground is one component without cavities.
//
// Betti numbers: b0 = 14-connected foreground components, b2 = cavities (14-connected background components that do
// not touch the grid's border), b1 = handles = b0 + b2 − χ, with χ = V − E + F − T counted over the foreground's
// simplices. The triangulation is a flag complex (a set of grid points is a simplex exactly when every two of them
// are 14-neighbours), which makes the simple-point test below local.
//
// A grid point is *simple* for a set G when moving it into or out of G changes the topology of neither G nor its
// complement (Bertrand & Malandain 1994, for this triangulation): the link of a point is a triangulated 2-sphere on
// its 14 neighbours, and the point is simple exactly when the neighbours in G, and those not in G, are each
// non-empty and connected along the link's edges (by Alexander duality, then both are contractible). Topology
// repair (topology_repair.hpp) grows sets by simple points only.

#include <array>
#include <cstdint>

#include "core/volume/binary_volume.hpp"

namespace wish::volume {

struct VoxelTopology {
  std::int64_t components = 0;  // b0
  std::int64_t handles = 0;     // b1 (the genus, for one component without cavities)
  std::int64_t cavities = 0;    // b2
  std::int64_t euler = 0;       // χ = b0 − b1 + b2
};

// Grid points outside the volume count as background.
VoxelTopology voxel_topology(const BinaryVolume& volume);

// The 14 neighbour offsets of a grid point: kuhn_offsets() and their negatives, in that order.
const std::array<std::array<int, 3>, 14>& link_offsets();

// `neighbours_in_set`: bit k set when the neighbour at link_offsets()[k] is in the set. True when the point is simple
// for that set (one lookup in a 2^14 table built once).
bool is_simple_point(std::uint32_t neighbours_in_set);

}  // namespace wish::volume
