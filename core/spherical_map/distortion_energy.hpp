#pragma once
// Isotropic distortion energies of one triangle's linear map (issue 37, the canonical map; canonical_map.hpp), as
// functions of its 2×2 deformation gradient F (reference triangle → mapped triangle, both in their own plane):
// value, gradient and a positive semidefinite projection of the Hessian for a Newton step (projected Newton,
// Teran et al. 2005; used for injective maps by Schmidt et al. 2019, "Distortion-minimizing injective maps between
// surfaces", and Liu et al. 2018, "Progressive parameterizations").
//
// Every energy here depends on F through its two invariants only, t = ‖F‖²_F = σ₁² + σ₂² and d = det F = σ₁σ₂
// (σ the singular values), so it is invariant to rotations of either triangle:
//   SymmetricDirichlet   ψ = σ₁² + σ₂² + σ₁⁻² + σ₂⁻² = t + t/d²    (≥ 4, = 4 iff F is a rotation: isometric)
//   ConformalArea(θ)     ψ = (1−θ)·t/d + θ·(d + 1/d)                  (≥ 2; θ = 0: MIPS, conformal only;
//                                                                       θ = 1: area only)
// Both are barriers: ψ → ∞ as d → 0⁺, so a minimiser never degenerates or flips a triangle (d > 0 is required).
// vec(F) is column-major: (F₀₀, F₁₀, F₀₁, F₁₁).

#include <string>

#include <Eigen/Core>

namespace wish::spherical {

enum class DistortionEnergyKind { SymmetricDirichlet, ConformalArea };
const char* to_string(DistortionEnergyKind kind);                       // "symmetric_dirichlet" | "conformal_area"
DistortionEnergyKind distortion_energy_from_name(const std::string& name);  // throws InvalidInputError

struct DistortionEnergy {
  DistortionEnergyKind kind = DistortionEnergyKind::SymmetricDirichlet;
  double area_weight = 0.5;  // θ of ConformalArea; ignored by SymmetricDirichlet
  bool operator==(const DistortionEnergy&) const = default;

  // The energy's least value (at an isometry): 4 for SymmetricDirichlet, 2 for ConformalArea.
  double minimum() const;
  // ψ(F); +infinity when det F ≤ 0.
  double value(const Eigen::Matrix2d& F) const;
  // ψ(F) and ∂ψ/∂F (2×2); requires det F > 0.
  double gradient(const Eigen::Matrix2d& F, Eigen::Matrix2d& dpsi_dF) const;
  // ∂²ψ/∂vec(F)² with its negative eigenvalues set to zero (positive semidefinite); requires det F > 0.
  Eigen::Matrix4d projected_hessian(const Eigen::Matrix2d& F) const;
};

}  // namespace wish::spherical
