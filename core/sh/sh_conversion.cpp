#include "core/sh/sh_conversion.hpp"

#include <cmath>

#include "core/sh/sh_basis.hpp"

namespace wish {

Eigen::MatrixXcd real_to_complex_coefficients(const Eigen::MatrixXd& real) {
  const int lmax = sh_lmax_from_count(real.rows());
  const double h = 1.0 / std::sqrt(2.0);
  Eigen::MatrixXcd out(real.rows(), real.cols());
  for (Eigen::Index q = 0; q < real.cols(); ++q)
    for (int l = 0; l <= lmax; ++l) {
      out(sh_index(l, 0), q) = real(sh_index(l, 0), q);
      for (int m = 1; m <= l; ++m) {
        const double ap = real(sh_index(l, m), q) * h, an = real(sh_index(l, -m), q) * h;
        const double sign = (m % 2) ? -1.0 : 1.0;
        out(sh_index(l, m), q) = {sign * ap, -sign * an};
        out(sh_index(l, -m), q) = {ap, an};
      }
    }
  return out;
}

Eigen::MatrixXd complex_to_real_coefficients(const Eigen::MatrixXcd& complex) {
  const int lmax = sh_lmax_from_count(complex.rows());
  const double r2 = std::sqrt(2.0);
  Eigen::MatrixXd out(complex.rows(), complex.cols());
  for (Eigen::Index q = 0; q < complex.cols(); ++q)
    for (int l = 0; l <= lmax; ++l) {
      out(sh_index(l, 0), q) = complex(sh_index(l, 0), q).real();
      for (int m = 1; m <= l; ++m) {
        const double sign = (m % 2) ? -1.0 : 1.0;
        out(sh_index(l, m), q) = r2 * sign * complex(sh_index(l, m), q).real();
        out(sh_index(l, -m), q) = -r2 * sign * complex(sh_index(l, m), q).imag();
      }
    }
  return out;
}

}  // namespace wish
