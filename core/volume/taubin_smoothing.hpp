#pragma once
// Light Taubin (lambda|mu) smoothing, as applied to segmentation meshes to remove the voxel staircase without
// the shrinkage of plain Laplacian smoothing (Taubin 1995). Uniform (umbrella) weights; topology untouched.

#include "core/mesh/mesh.hpp"

namespace wish::volume {

void taubin_smooth(Mesh& mesh, int iterations, double lambda = 0.5, double mu = -0.53);

}  // namespace wish::volume
