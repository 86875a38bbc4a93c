#pragma once
// Weighted Gram matrix G = Y^T diag(w) Y of the real SH basis of degree Lmax at n points (k x k, k = (Lmax+1)^2):
// the left-hand side of the fit's normal equations (paper Eq. 12).
//
// GramMethod::Product: Y (n x k) is formed and G accumulated by a blocked symmetric rank-n update; n k^2 flops.
// GramMethod::Quadrature (default): exact up to rounding at a fraction of the cost. A product S_i S_j of two
//   harmonics of degree <= L is a combination of harmonics of degree <= 2L, so
//     G_ij = sum_p w_p S_i(u_p) S_j(u_p) = integral over the sphere of S_i S_j g,
//   where g = sum_{J: deg <= 2L} mu_J S_J and mu_J = sum_p w_p S_J(u_p) are the degree-2L moments of the weighted
//   points (n (2L+1)^2 work, no n x k matrix). The integral is evaluated exactly: Gauss-Legendre in cos t with
//   2L+1 nodes (exact to polynomial degree 4L+1 >= 4L) and analytic integration in p from the Fourier
//   coefficients of g on each node's ring, block by block in (m, m'); (2L+1) k^2 flops.
//   Both paths agree to ~1e-14 relative (tests/sh/sh_fit_test.cpp, ShGram.QuadratureEqualsProduct).

#include <Eigen/Core>

#include "core/sh/sh_descriptor.hpp"

namespace wish {

Eigen::MatrixXd sh_gram_matrix(int lmax, const Eigen::MatrixX3d& points, const Eigen::VectorXd& weights,
                               GramMethod method = GramMethod::Quadrature);

// n-point Gauss-Legendre rule on [-1, 1] (nodes ascending), by Newton iteration on P_n.
void gauss_legendre(int n, Eigen::VectorXd& nodes, Eigen::VectorXd& weights);

}  // namespace wish
