#pragma once
// Scalar mean curvature and Willmore energy (docs/design/spherical-map.md §1).
//   Mean-curvature normal: (L x)_i ≈ 2 M_i H_i N_i with the PSD cot Laplacian L and lumped mass M.
//   H_i = N_i·(L x)_i / (2 M_i),  H = (κ1 + κ2)/2,  sign: H > 0 on a convex surface with outward normals
//   (unit sphere: H ≡ 1). Units: 1/length.
//   Willmore energy E_W = ∫ H² dA ≈ Σ_i M_i H_i²: dimensionless, ≥ 4π on closed surfaces, 4π on the round sphere.
//   (The paper's Eq. (1) ∫(H² − K) dA is E_W − 4π for genus 0.)

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace wish::geometry {

Eigen::VectorXd mean_curvature(const Eigen::MatrixX3d& vertices, const Eigen::SparseMatrix<double>& laplacian,
                               const Eigen::VectorXd& mass, const Eigen::MatrixX3d& normals);
// Convenience: computes L, M and angle-weighted normals.
Eigen::VectorXd mean_curvature(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces);

double willmore_energy(const Eigen::VectorXd& mean_curvature, const Eigen::VectorXd& mass);
double willmore_energy(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces);

}  // namespace wish::geometry
