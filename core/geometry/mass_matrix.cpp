#include "core/geometry/mass_matrix.hpp"

#include "core/geometry/face_geometry.hpp"

namespace wish::geometry {

Eigen::VectorXd lumped_mass(const Eigen::MatrixX3i& faces, const Eigen::VectorXd& face_areas, Eigen::Index vertex_count) {
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(vertex_count);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) mass[faces(f, k)] += face_areas[f] / 3.0;
  return mass;
}

Eigen::VectorXd lumped_mass(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
  return lumped_mass(faces, face_areas(vertices, faces), vertices.rows());
}

}  // namespace wish::geometry
