#pragma once
// How far a closed surface is from a round sphere (docs/design/spherical-map.md §7):
//   c = Σ_i M_i x_i / Σ_i M_i (area-weighted centroid), r_i = ‖x_i − c‖,  R = std_i(r_i) / mean_i(r_i)
// (dimensionless; 0 for vertices on a sphere about c).

#include <Eigen/Core>

namespace wish::geometry {

Eigen::Vector3d area_weighted_centroid(const Eigen::MatrixX3d& vertices, const Eigen::VectorXd& mass);
double roundness(const Eigen::MatrixX3d& vertices, const Eigen::VectorXd& mass);
double roundness(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces);

}  // namespace wish::geometry
