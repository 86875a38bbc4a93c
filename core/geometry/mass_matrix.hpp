#pragma once
// Lumped (barycentric) mass: M_i = Σ_{f∋i} A_f / 3 (units²). Σ_i M_i = total area.

#include <Eigen/Core>

namespace wish::geometry {

Eigen::VectorXd lumped_mass(const Eigen::MatrixX3i& faces, const Eigen::VectorXd& face_areas, Eigen::Index vertex_count);
Eigen::VectorXd lumped_mass(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces);

}  // namespace wish::geometry
