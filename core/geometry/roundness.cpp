#include "core/geometry/roundness.hpp"

#include <cmath>

#include "core/geometry/mass_matrix.hpp"

namespace wish::geometry {

Eigen::Vector3d area_weighted_centroid(const Eigen::MatrixX3d& vertices, const Eigen::VectorXd& mass) {
  return (vertices.transpose() * mass) / mass.sum();
}

double roundness(const Eigen::MatrixX3d& vertices, const Eigen::VectorXd& mass) {
  const Eigen::Vector3d c = area_weighted_centroid(vertices, mass);
  const Eigen::VectorXd r = (vertices.rowwise() - c.transpose()).rowwise().norm();
  const double mean = r.mean();
  const double var = (r.array() - mean).square().mean();
  return std::sqrt(var) / mean;
}

double roundness(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
  return roundness(vertices, lumped_mass(vertices, faces));
}

}  // namespace wish::geometry
