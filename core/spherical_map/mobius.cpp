#include "core/spherical_map/mobius.hpp"

#include <cmath>

#include <Eigen/Cholesky>

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

// The Newton step for the boost, taken at a = 0 of the CURRENT map (each accepted step re-centres the map, so the
// next step starts at 0 again). F(a) = Σ w_i log(|u_i − a|² / (1 − |a|²)) (Σ w_i = 1) has, at a = 0,
//   ∇F = −2c,  ∇²F = 4 (I − S),  c = Σ w_i u_i,  S = Σ w_i u_i u_iᵀ  (trace S = 1, so I − S ⪰ 0),
// and Σ w_i T_a(u_i) = −(1 − |a|²)/2 ∇F(a): the balanced map is F's stationary point. Newton: a = ½ (I − S)⁻¹ c.
// For an even spread of weight (S = I/3) that is 0.75 c, close to the damped fixed point's 0.5 c; when the weight
// sits near two antipodal caps (the map of a long shape: S has an eigenvalue near 1) the fixed point crawls along
// that axis and Newton does not.
Eigen::Vector3d newton_boost(const Eigen::MatrixX3d& sphere, const Eigen::VectorXd& w, const Eigen::Vector3d& c) {
  const Eigen::Matrix3d s = sphere.transpose() * w.asDiagonal() * sphere;
  const Eigen::Matrix3d h = Eigen::Matrix3d::Identity() - s;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(h);
  Eigen::Vector3d a = 0.5 * ldlt.solve(c);
  if (ldlt.info() != Eigen::Success || !a.allFinite() || a.dot(c) <= 0) a = 0.5 * c;  // (I − S) singular: all weight on one axis
  return a;
}

}  // namespace

MobiusResult mobius_balance(Eigen::MatrixX3d& sphere, const Eigen::VectorXd& weights, const MobiusOptions& options) {
  MobiusResult result;
  const Eigen::VectorXd w = weights / weights.sum();
  auto centroid = [&] { return Eigen::Vector3d(sphere.transpose() * w); };
  Eigen::Vector3d c = centroid();
  for (int it = 0; it < options.max_iterations; ++it) {
    result.centroid = c.norm();
    if (!(result.centroid >= options.tolerance)) break;  // also stops on NaN
    // A Newton step, kept inside the ball and halved until the centroid shrinks (a line search on |c|).
    Eigen::Vector3d a = newton_boost(sphere, w, c);
    if (a.norm() > options.max_boost) a *= options.max_boost / a.norm();
    const Eigen::MatrixX3d before = sphere;
    bool accepted = false;
    for (int halvings = 0; halvings < options.max_halvings && !accepted; ++halvings, a *= 0.5) {
      apply_mobius(sphere, a);
      const Eigen::Vector3d next = centroid();
      if (next.norm() < result.centroid) {
        c = next;
        accepted = true;
      } else {
        sphere = before;
      }
    }
    ++result.iterations;
    if (!accepted) break;  // no boost along the Newton direction lowers |c|: round-off level
  }
  result.centroid = c.norm();
  result.converged = result.centroid < options.tolerance;
  return result;
}

}  // namespace wish::spherical
