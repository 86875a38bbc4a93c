#include "core/spherical_map/mobius.hpp"

#include <cmath>

namespace wish::spherical {
namespace {

void apply_mobius(Eigen::MatrixX3d& sphere, const Eigen::Vector3d& a) {
  const double a2 = a.squaredNorm();
  for (Eigen::Index i = 0; i < sphere.rows(); ++i) {
    const Eigen::Vector3d u = sphere.row(i);
    const Eigen::Vector3d d = u - a;
    Eigen::Vector3d v = (1.0 - a2) * d / d.squaredNorm() - a;
    sphere.row(i) = v.normalized();
  }
}

}  // namespace

MobiusResult mobius_balance(Eigen::MatrixX3d& sphere, const Eigen::VectorXd& weights, const MobiusOptions& options) {
  MobiusResult result;
  const Eigen::VectorXd w = weights / weights.sum();
  auto centroid = [&] { return Eigen::Vector3d(sphere.transpose() * w); };
  Eigen::Vector3d c = centroid();
  double alpha = options.damping;
  for (int it = 0; it < options.max_iterations; ++it) {
    result.centroid = c.norm();
    if (!(result.centroid >= options.tolerance)) break;  // also stops on NaN
    const Eigen::MatrixX3d before = sphere;
    apply_mobius(sphere, alpha * c);
    ++result.iterations;
    const Eigen::Vector3d next = centroid();
    if (next.norm() > result.centroid) {  // overshoot: undo and damp harder
      sphere = before;
      alpha *= 0.5;
      if (alpha < 1e-6) break;
      continue;
    }
    c = next;
  }
  result.centroid = c.norm();
  result.converged = result.centroid < options.tolerance;
  return result;
}

}  // namespace wish::spherical
