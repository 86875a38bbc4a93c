#pragma once
// Rotation-invariant energies (paper Eq. 14, Kazhdan 2003), summed over the three coordinates:
//   xi(l) = sum_{m=-l..l} sum_{c in x,y,z} |c_{l,c}^m|^2,  l = 0..Lmax.
// Invariant to rotations of the object and of the sphere domain, to reflections, and (l >= 1) to translations;
// xi(0) ~ 4 pi |centroid|^2 depends on translation. Equal for real and complex coefficients.

#include <complex>

#include <Eigen/Core>

namespace wish {

using ShCoefficients = Eigen::Matrix<std::complex<double>, Eigen::Dynamic, 3>;

Eigen::VectorXd sh_invariants(const ShCoefficients& coefficients);
Eigen::VectorXd sh_invariants_real(const Eigen::MatrixX3d& real_coefficients);

// Scale-normalised variant xi(l) / xi(1) (xi(1) = 0 gives zeros).
Eigen::VectorXd scale_normalized_invariants(const Eigen::VectorXd& invariants);

}  // namespace wish
