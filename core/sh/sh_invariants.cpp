#include "core/sh/sh_invariants.hpp"

#include "core/sh/sh_basis.hpp"

namespace wish {

Eigen::VectorXd sh_invariants(const ShCoefficients& coefficients) {
  const int lmax = sh_lmax_from_count(coefficients.rows());
  Eigen::VectorXd xi = Eigen::VectorXd::Zero(lmax + 1);
  for (int l = 0; l <= lmax; ++l)
    xi[l] = coefficients.middleRows(sh_index(l, -l), 2 * l + 1).cwiseAbs2().sum();
  return xi;
}

Eigen::VectorXd sh_invariants_real(const Eigen::MatrixX3d& real_coefficients) {
  const int lmax = sh_lmax_from_count(real_coefficients.rows());
  Eigen::VectorXd xi = Eigen::VectorXd::Zero(lmax + 1);
  for (int l = 0; l <= lmax; ++l) xi[l] = real_coefficients.middleRows(sh_index(l, -l), 2 * l + 1).squaredNorm();
  return xi;
}

Eigen::VectorXd scale_normalized_invariants(const Eigen::VectorXd& invariants) {
  if (invariants.size() < 2 || invariants[1] == 0) return Eigen::VectorXd::Zero(invariants.size());
  return invariants / invariants[1];
}

}  // namespace wish
