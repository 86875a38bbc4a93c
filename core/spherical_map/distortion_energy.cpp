#include "core/spherical_map/distortion_energy.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "core/common/enum_names.hpp"

namespace wish::spherical {
namespace {

inline constexpr EnumNames<DistortionEnergyKind, 2> kDistortionEnergyNames{{{
    {DistortionEnergyKind::SymmetricDirichlet, "symmetric_dirichlet"},
    {DistortionEnergyKind::ConformalArea, "conformal_area"}}}};

// ψ as a function of the invariants t = ‖F‖², d = det F, with its first and second partial derivatives.
struct InvariantDerivatives {
  double psi = 0, t = 0, d = 0, tt = 0, td = 0, dd = 0;
};

InvariantDerivatives derivatives(const DistortionEnergy& e, double t, double d) {
  InvariantDerivatives r;
  if (e.kind == DistortionEnergyKind::SymmetricDirichlet) {
    // ψ = t (1 + d⁻²)
    const double inv2 = 1.0 / (d * d), inv3 = inv2 / d;
    r.psi = t * (1.0 + inv2);
    r.t = 1.0 + inv2;
    r.d = -2.0 * t * inv3;
    r.td = -2.0 * inv3;
    r.dd = 6.0 * t * inv3 / d;
  } else {
    // ψ = (1−θ) t/d + θ (d + 1/d)
    const double c = 1.0 - e.area_weight, a = e.area_weight;
    const double inv = 1.0 / d, inv2 = inv * inv, inv3 = inv2 * inv;
    r.psi = c * t * inv + a * (d + inv);
    r.t = c * inv;
    r.d = -c * t * inv2 + a * (1.0 - inv2);
    r.td = -c * inv2;
    r.dd = 2.0 * c * t * inv3 + 2.0 * a * inv3;
  }
  return r;
}

// vec(F) column-major and the gradient of det F in that order.
Eigen::Vector4d vec(const Eigen::Matrix2d& F) { return {F(0, 0), F(1, 0), F(0, 1), F(1, 1)}; }
Eigen::Vector4d det_gradient(const Eigen::Matrix2d& F) { return {F(1, 1), -F(0, 1), -F(1, 0), F(0, 0)}; }

}  // namespace

const char* to_string(DistortionEnergyKind kind) { return kDistortionEnergyNames.name(kind); }

DistortionEnergyKind distortion_energy_from_name(const std::string& name) {
  return kDistortionEnergyNames.parse(name, "distortion energy", "energy");
}

double DistortionEnergy::minimum() const { return kind == DistortionEnergyKind::SymmetricDirichlet ? 4.0 : 2.0; }

double DistortionEnergy::value(const Eigen::Matrix2d& F) const {
  const double d = F.determinant();
  if (!(d > 0)) return std::numeric_limits<double>::infinity();
  return derivatives(*this, F.squaredNorm(), d).psi;
}

double DistortionEnergy::gradient(const Eigen::Matrix2d& F, Eigen::Matrix2d& dpsi_dF) const {
  const double d = F.determinant();
  const InvariantDerivatives r = derivatives(*this, F.squaredNorm(), d);
  // ∂t/∂F = 2F, ∂d/∂F = cof F = d F⁻ᵀ.
  Eigen::Matrix2d cof;
  cof << F(1, 1), -F(1, 0), -F(0, 1), F(0, 0);
  dpsi_dF = 2.0 * r.t * F + r.d * cof;
  return r.psi;
}

Eigen::Matrix4d DistortionEnergy::projected_hessian(const Eigen::Matrix2d& F) const {
  const double d = F.determinant();
  const InvariantDerivatives r = derivatives(*this, F.squaredNorm(), d);
  const Eigen::Vector4d a = 2.0 * vec(F), b = det_gradient(F);
  // ∂²d/∂vec(F)²: d = F₀₀F₁₁ − F₀₁F₁₀.
  Eigen::Matrix4d hess_d = Eigen::Matrix4d::Zero();
  hess_d(0, 3) = hess_d(3, 0) = 1.0;
  hess_d(1, 2) = hess_d(2, 1) = -1.0;
  Eigen::Matrix4d H = 2.0 * r.t * Eigen::Matrix4d::Identity() + r.d * hess_d + r.tt * a * a.transpose() +
                      r.dd * b * b.transpose() + r.td * (a * b.transpose() + b * a.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(H);
  const Eigen::Vector4d lambda = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace wish::spherical
