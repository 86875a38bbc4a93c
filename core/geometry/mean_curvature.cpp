#include "core/geometry/mean_curvature.hpp"

#include "core/geometry/cotan_laplacian.hpp"
#include "core/geometry/mass_matrix.hpp"
#include "core/geometry/vertex_normals.hpp"

namespace wish::geometry {

Eigen::VectorXd mean_curvature(const Eigen::MatrixX3d& vertices, const Eigen::SparseMatrix<double>& laplacian,
                               const Eigen::VectorXd& mass, const Eigen::MatrixX3d& normals) {
  const Eigen::MatrixX3d lx = laplacian * vertices;
  Eigen::VectorXd h(vertices.rows());
  for (Eigen::Index i = 0; i < h.size(); ++i) h[i] = normals.row(i).dot(lx.row(i)) / (2.0 * mass[i]);
  return h;
}

Eigen::VectorXd mean_curvature(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
  return mean_curvature(vertices, cotan_laplacian(vertices, faces), lumped_mass(vertices, faces),
                        vertex_normals(vertices, faces));
}

double willmore_energy(const Eigen::VectorXd& mean_curvature, const Eigen::VectorXd& mass) {
  return (mass.array() * mean_curvature.array().square()).sum();
}

double willmore_energy(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
  return willmore_energy(mean_curvature(vertices, faces), lumped_mass(vertices, faces));
}

}  // namespace wish::geometry
