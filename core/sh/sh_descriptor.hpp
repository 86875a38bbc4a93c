#pragma once
// Spherical-harmonics descriptor of a mapped mesh (paper §5, docs/design/sh-and-invariants.md).
// Conventions: u = (sin t cos p, sin t sin p, cos t); complex Y_l^m orthonormal with Condon-Shortley phase;
// coefficient index j = l^2 + l + m (0-based), k = (Lmax+1)^2 coefficients per coordinate.

#include <complex>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/mesh/mesh.hpp"
#include "core/sh/sh_lmax_range.hpp"  // kShMinFitLmax, kShMaxFitLmax: the Lmax the fit accepts

namespace wish {

enum class FitWeighting { Area, Uniform };  // area: input vertex areas (default); uniform: the paper's
enum class FitSolver { Direct, Banded };    // one LDLT solve; or the paper's residual banded scheme
// How the k x k Gram matrix Y^T W Y is built (both exact up to rounding, see core/sh/sh_gram.hpp):
//   Quadrature: from the degree-2*Lmax moments of the weighted points, O(n Lmax^2 + Lmax^5) (default);
//   Product:    blocked matrix product of the n x k basis matrix, O(n k^2).
enum class GramMethod { Quadrature, Product };
// Where the fit's objective is sampled (issue 37 item 3): at the input's vertices with `weighting` (the paper's fit;
// recipes before version 4), or over the input's surface by quadrature (surface_quadrature.hpp: area weights over
// sub-triangles, so the objective and ξ do not depend on how finely the shape is triangulated).
enum class FitSampling { Vertices, Surface };

const char* to_string(FitWeighting weighting);
const char* to_string(FitSolver solver);
const char* to_string(GramMethod method);
const char* to_string(FitSampling sampling);
// Inverses of to_string ("area" | "uniform", "direct" | "banded", "quadrature" | "product"); throw InvalidInputError.
FitWeighting fit_weighting_from_name(const std::string& name);
FitSolver fit_solver_from_name(const std::string& name);
GramMethod gram_method_from_name(const std::string& name);
FitSampling fit_sampling_from_name(const std::string& name);  // "vertices" | "surface"

struct ShFitOptions {
  int lmax = 15;
  // nu in the paper's units (Eq. 11-13): the penalty nu l^2 (l+1)^2 as the paper applied it to the unweighted
  // normal equations of a 10^4-vertex mesh. The fit uses weights summing to 1 and the penalty nu/10^4 l^2 (l+1)^2,
  // which is the paper's fit at 10^4 vertices and independent of the resolution (sh_fit.cpp).
  double regularization = 1e-5;
  FitWeighting weighting = FitWeighting::Area;
  FitSolver solver = FitSolver::Direct;
  int band_size = 100;            // max coefficients per band for the banded solver
  GramMethod gram = GramMethod::Quadrature;
  FitSampling sampling = FitSampling::Vertices;  // Surface: weighting is ignored (the surface's own area measure)
  bool operator==(const ShFitOptions&) const = default;
};

struct FitError {
  double mean = 0, rms = 0, max = 0;                   // |x_i - x_L(w_i)| in input units
  double mean_relative = 0, rms_relative = 0, max_relative = 0;  // divided by the bounding-box diagonal
};

struct ShDescriptor {
  int lmax = 0;
  // k by 3 complex coefficients c_l^m of x, y, z (column 0, 1, 2), row j = l^2 + l + m.
  Eigen::Matrix<std::complex<double>, Eigen::Dynamic, 3> coefficients;
  // Lmax+1 rotation-invariant energies xi(l) = sum_m sum_{x,y,z} |c_l^m|^2 (paper Eq. 14); xi(0) is translation-dependent.
  Eigen::VectorXd invariants;
  FitError fit_error;
  ShFitOptions options;
};

}  // namespace wish
