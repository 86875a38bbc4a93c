#pragma once
// Surface of a binary label volume by marching tetrahedra on the Kuhn triangulation (each cube split into 6
// tetrahedra along its (1,1,1) diagonal, consistently across cubes). Chosen over marching cubes because it
// has no ambiguous cases: the surface is the level set 1/2 of the piecewise-linear interpolant, which is
// always a closed 2-manifold when the border voxels are background; its vertices sit at the midpoints of
// grid edges joining a foreground to a background point (the staircase of real label meshes, smoothed after).
// Faces are oriented outward (counter-clockwise seen from the background).

#include "core/mesh/mesh.hpp"
#include "core/volume/binary_volume.hpp"

namespace wish::volume {

Mesh marching_tetrahedra(const BinaryVolume& volume);

}  // namespace wish::volume
