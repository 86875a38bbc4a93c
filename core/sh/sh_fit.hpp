#pragma once
// Regularised least-squares fit of the coordinate functions x, y, z on the sphere map (paper Eq. 10-13;
// docs/design/sh-and-invariants.md):
//
//   C = argmin  sum_i w_i |Y(u_i) C - X_i|^2 + nu |Gamma C|^2,   Gamma = diag(l_j (l_j + 1)),
//
// i.e. R = Gamma^T Gamma = diag(l^2 (l+1)^2), the biharmonic penalty. NOTE: the paper prints R = diag(l^2 (l^2+1)^2);
// that is a typo (the squared spherical Laplacian has eigenvalues l^2 (l+1)^2). Weights are normalised to sum to 1
// so that nu means the same at every resolution; area weights (lumped vertex mass of the INPUT mesh) by default,
// uniform (the paper) as option. The fit is done in the real orthonormal basis (k = (Lmax+1)^2 real unknowns per
// coordinate) by one symmetric LDL^T factorisation of (Y^T W Y + nu R) for the three right-hand sides, and the
// coefficients are converted to the complex c_l^m (core/sh/sh_conversion.hpp). The paper's residual banded scheme:
// FitSolver::Banded (bands of whole degrees, at most band_size coefficients each; a degree with more than
// band_size functions is a band of its own; band s fits the residual of bands < s).
// Scaling the input by s scales C by s exactly (weights are normalised), invariants by s^2.

#include <Eigen/Core>

#include "core/mesh/mesh.hpp"
#include "core/sh/sh_descriptor.hpp"

namespace wish {


// The fit weights of `options.weighting` for `input`, normalised to sum 1.
// Throws InvalidInputError ("degenerate_mesh") when the area weights sum to zero.
Eigen::VectorXd fit_weights(const Mesh& input, FitWeighting weighting);

// Real coefficients (k x 3) of targets X (n x 3) at sphere points (n x 3) with weights (n; normalised here).
// Uses options.lmax, regularization, solver, band_size, gram (options.weighting is ignored).
Eigen::MatrixX3d fit_real_sh(const Eigen::MatrixX3d& sphere_points, const Eigen::MatrixX3d& targets,
                             const Eigen::VectorXd& weights, const ShFitOptions& options);

// Fit error of real coefficients against targets at the sphere points (mean / RMS / max over the points,
// unweighted, as paper Fig. 6), relative values divided by the bounding-box diagonal of the targets.
FitError sh_fit_error(const Eigen::MatrixX3d& sphere_points, const Eigen::MatrixX3d& targets,
                      const Eigen::MatrixX3d& real_coefficients);

// The whole descriptor: weights, fit, complex coefficients, invariants, fit error.
// Throws InvalidInputError on bad options ("invalid_parameter"), mismatched sizes, non-finite or zero sphere
// points, and LimitExceededError for lmax > kShMaxFitLmax.
ShDescriptor fit_spherical_harmonics(const Mesh& input, const Eigen::MatrixX3d& sphere_points,
                                     const ShFitOptions& options = {});

}  // namespace wish
