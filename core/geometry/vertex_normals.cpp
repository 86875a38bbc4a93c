#include "core/geometry/vertex_normals.hpp"

#include <cmath>

#include <Eigen/Geometry>

namespace wish::geometry {

Eigen::MatrixX3d vertex_normals(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
  Eigen::MatrixX3d normals = Eigen::MatrixX3d::Zero(vertices.rows(), 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d x0 = vertices.row(faces(f, 0));
    const Eigen::Vector3d x1 = vertices.row(faces(f, 1));
    const Eigen::Vector3d x2 = vertices.row(faces(f, 2));
    Eigen::Vector3d n = (x1 - x0).cross(x2 - x0);
    const double len = n.norm();
    if (!(len > 0)) continue;
    n /= len;
    const Eigen::Vector3d p[3] = {x0, x1, x2};
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d u = p[(k + 1) % 3] - p[k];
      const Eigen::Vector3d v = p[(k + 2) % 3] - p[k];
      const double angle = std::atan2(u.cross(v).norm(), u.dot(v));
      normals.row(faces(f, k)) += angle * n.transpose();
    }
  }
  for (Eigen::Index i = 0; i < normals.rows(); ++i) {
    const double len = normals.row(i).norm();
    if (len > 0) normals.row(i) /= len;
  }
  return normals;
}

}  // namespace wish::geometry
