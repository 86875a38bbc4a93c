#pragma once
// Nucleus-like shapes for the synthetic demo set (docs/design/classification.md "The demo data set"): per class size,
// elongation, flattening, lobulation, invaginations and surface roughness, plus bending for the cells that wrap
// around capillaries (endothelium, pericyte). A shape is star-shaped about its centre in an ellipsoidal frame
// (inside iff rho < 1 + f(direction)) and then bent by a diffeomorphism, so it is topologically a ball; the
// voxelised result is still verified (demo_dataset.cpp), since a voxel grid can pinch thin parts.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace wish::synth {

struct Bump {
  Eigen::Vector3d direction;  // unit, in the ellipsoid's normalised frame
  double amplitude = 0;       // > 0 lobe, < 0 invagination (relative radius)
  double width = 0.1;         // angular width: exp(-(1 - u.d) / width)
};

struct NucleusShape {
  double a = 4, b = 3.5, c = 3;       // semi-axes (µm), a >= b >= c
  double bend = 0;                    // curvature (1/µm) of the long axis, bending towards +z
  std::vector<Bump> bumps;            // lobes, invaginations and roughness
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // local -> world
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();         // world (µm)

  bool inside(const Eigen::Vector3d& world) const;
  double radius_factor(const Eigen::Vector3d& unit) const;  // 1 + f(u), floored at 0.25
  double bounding_radius() const;                           // encloses the shape around `centre`
};

// The paper's six classes (§6), in this order.
const std::vector<std::string>& demo_classes();

// One random shape of class `class_index`, deterministic in `seed`.
NucleusShape sample_nucleus_shape(int class_index, std::uint64_t seed);

}  // namespace wish::synth
