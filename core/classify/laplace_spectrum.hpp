#pragma once
// ShapeDNA (Reuter, Wolter & Peinecke, "Laplace-Beltrami spectra as 'Shape-DNA' of surfaces and solids",
// Computer-Aided Design 38, 2006): the first eigenvalues of the Laplace-Beltrami operator of the surface, an
// INTRINSIC descriptor — it depends on the metric only, so it is invariant to rigid motions and to isometric bending
// (a cell that bends, an articulated shape that poses), which the conformal map's xi(l) are not.
//
// Discretisation: the robust cotan Laplacian of core/geometry/intrinsic_laplacian.hpp (mollified edge lengths,
// intrinsic Delaunay flips: every weight >= 0, so raw marching-cubes meshes with slivers give a valid operator) and
// its lumped intrinsic mass; the generalised problem L u = λ M u (PSD convention: λ >= 0), solved by shift-invert
// block Krylov on a CHOLMOD factor (core/linalg/generalized_eigen.hpp).
// Normalisation (scale): λ scales as 1/length²; the reported values are λ_i · A / (4π) with A the surface area,
// so that the unit sphere's values are l(l+1) (0, 2 ×3, 6 ×5, 12 ×7, ...) at any size: uniform scaling leaves them
// unchanged (Reuter et al. §4.3 normalise by area the same way). λ_0 = 0 (the constants) is dropped.

#include <Eigen/Core>

#include "core/mesh/mesh.hpp"

namespace wish {

// The number of eigenvalues a recipe's spectrum family uses unless it says otherwise (docs/accuracy.md, issue 38).
inline constexpr int kDefaultSpectrumCount = 20;
inline constexpr int kMaxSpectrumCount = 200;

struct LaplaceSpectrum {
  Eigen::VectorXd values;     // λ_1..λ_count · A/(4π), ascending
  double zero_mode = 0;       // λ_0 · A/(4π) as computed (|.| <= 1e-6 expected: a closed connected surface)
  double max_residual = 0;    // largest relative residual of the eigenpairs (generalized_eigen.hpp)
  int cycles = 0;             // Krylov restart cycles
};

// count in 1..kMaxSpectrumCount. Throws InvalidInputError("invalid_parameter") for a bad count, WishError(Unmappable, "too_small") for
// a mesh of fewer vertices than count + 1, WishError(Internal, "spectrum_failed") when the factorisation fails or
// the eigenpairs do not converge (the message has the residual).
LaplaceSpectrum laplace_spectrum(const Mesh& mesh, int count = kDefaultSpectrumCount);

}  // namespace wish
