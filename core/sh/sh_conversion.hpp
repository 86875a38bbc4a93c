#pragma once
// Real <-> complex spherical-harmonic coefficients of REAL functions (conventions: core/sh/sh_basis.hpp).
// With f = sum_j a_j S_j = sum_j c_j Y_j:
//   c_l^0 = a_l^0;  c_l^m = (-1)^m (a_l^m - i a_l^{-m}) / sqrt2,  c_l^{-m} = (a_l^m + i a_l^{-m}) / sqrt2  (m > 0),
// so that c_l^{-m} = (-1)^m conj(c_l^m), and sum_m |c_l^m|^2 = sum_m (a_l^m)^2 for every l.
// Inverse: a_l^m = sqrt2 (-1)^m Re c_l^m,  a_l^{-m} = -sqrt2 (-1)^m Im c_l^m  (uses only m >= 0 of c).
// Rows are indexed j = l^2 + l + m; columns are independent functions (x, y, z).

#include <Eigen/Core>

namespace wish {

Eigen::MatrixXcd real_to_complex_coefficients(const Eigen::MatrixXd& real);
Eigen::MatrixXd complex_to_real_coefficients(const Eigen::MatrixXcd& complex);

}  // namespace wish
