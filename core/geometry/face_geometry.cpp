#include "core/geometry/face_geometry.hpp"

#include <cmath>

#include <Eigen/Geometry>

namespace wish::geometry {

Eigen::VectorXd face_areas(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
  Eigen::VectorXd areas(faces.rows());
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d x0 = vertices.row(faces(f, 0));
    const Eigen::Vector3d x1 = vertices.row(faces(f, 1));
    const Eigen::Vector3d x2 = vertices.row(faces(f, 2));
    areas[f] = 0.5 * (x1 - x0).cross(x2 - x0).norm();
  }
  return areas;
}

Eigen::MatrixX3d corner_cotangents(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
  Eigen::MatrixX3d cot(faces.rows(), 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = vertices.row(faces(f, k));
      const Eigen::Vector3d u = Eigen::Vector3d(vertices.row(faces(f, (k + 1) % 3))) - p;
      const Eigen::Vector3d v = Eigen::Vector3d(vertices.row(faces(f, (k + 2) % 3))) - p;
      cot(f, k) = u.dot(v) / u.cross(v).norm();
    }
  }
  return cot;
}

Eigen::MatrixX3d corner_angles(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
  Eigen::MatrixX3d angles(faces.rows(), 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = vertices.row(faces(f, k));
      const Eigen::Vector3d u = Eigen::Vector3d(vertices.row(faces(f, (k + 1) % 3))) - p;
      const Eigen::Vector3d v = Eigen::Vector3d(vertices.row(faces(f, (k + 2) % 3))) - p;
      angles(f, k) = std::atan2(u.cross(v).norm(), u.dot(v));
    }
  }
  return angles;
}

double signed_volume(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
  double volume = 0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d x0 = vertices.row(faces(f, 0));
    const Eigen::Vector3d x1 = vertices.row(faces(f, 1));
    const Eigen::Vector3d x2 = vertices.row(faces(f, 2));
    volume += x0.dot(x1.cross(x2));
  }
  return volume / 6.0;
}

double mean_edge_length(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
  if (faces.rows() == 0) return 0;
  double sum = 0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      sum += (vertices.row(faces(f, (k + 1) % 3)) - vertices.row(faces(f, k))).norm();
  return sum / (3.0 * static_cast<double>(faces.rows()));
}

}  // namespace wish::geometry
