#pragma once
// Rotation-invariant global shape descriptors computed from the mesh itself (issue 5: "an optional second
// family ... volume, area, sphericity, ratios of the inertia tensor's eigenvalues; scale-free variants too").
// They complement the spectral energies xi(l) of paper Eq. 14, which see the map-dependent shape spectrum but
// not, e.g., total size directly. All are invariant to rotation and translation; the ones marked scale-free
// are also invariant to uniform scaling. Input: a closed, outward-oriented triangle mesh.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/mesh/mesh.hpp"

namespace wish {

// Order of the entries of global_shape_descriptors(); stored by name in the model file.
enum GlobalDescriptor : int {
  kGlobalVolume = 0,            // |enclosed volume|                       [length^3]
  kGlobalArea,                  // surface area                            [length^2]
  kGlobalEquivalentRadius,      // (3V / 4 pi)^(1/3)                        [length]
  kGlobalSphericity,            // pi^(1/3) (6V)^(2/3) / A, 1 for a sphere  scale-free
  kGlobalElongation,            // sqrt(l2 / l1), l1 >= l2 >= l3 eigenvalues of the solid's second-moment tensor
  kGlobalFlatness,              // sqrt(l3 / l2)
  kGlobalAxisRatio,             // sqrt(l3 / l1)
  kGlobalEllipsoidAreaRatio,    // A / area of the ellipsoid with the same moments (lobulation, roughness)
  kGlobalMeanCurvatureRatio,    // integral of H dA / sqrt(4 pi A): 1 for a sphere
  kGlobalAbsMeanCurvatureRatio, // integral of |H| dA / sqrt(4 pi A)
  kGlobalConcaveAreaFraction,   // share of edge weight on concave (saddle/invaginated) edges
  kGlobalCount
};

const std::vector<std::string>& global_descriptor_names();
bool global_descriptor_is_scale_free(int index);

// Throws InvalidInputError("empty_mesh") for a mesh without faces or with zero volume.
Eigen::VectorXd global_shape_descriptors(const Mesh& mesh);

}  // namespace wish
