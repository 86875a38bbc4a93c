#pragma once
// The SH coefficients themselves as a descriptor (issue 38 item 2a): xi(l) is a power spectrum and discards the
// phases that tell a local bump from a smooth surface; the coefficients keep them, but they depend on the object's
// rotation in space AND on the rotation of the parameterisation on the sphere. Both are fixed here by the
// first-order ellipsoid, as SPHARM-PDM (Brechbühler, Gerig & Kübler 1995, §4; Styner et al. 2006) and aics-shparam
// align:
//   the degree-1 part of the fitted surface is an ellipsoid x1(u) = G u (G: 3x3, space x sphere direction, from the
//   degree-1 real coefficients). With G = U Σ Vᵀ (σ1 >= σ2 >= σ3), the object is rotated by Uᵀ (x' = Uᵀ x: the
//   ellipsoid's axes on x, y, z, longest first) and the parameter by V (u = V u'), so that x1'(u') = Σ u'.
//   The coefficients of x'(u') = Uᵀ x(V u') are computed exactly by Gauss-Legendre x trapezoid quadrature (exact
//   for band-limited functions of degree <= 2 Lmax).
// Ambiguities, resolved and reported:
//   * sign: (u_i, v_i) -> (-u_i, -v_i) leaves G unchanged. U is made a proper rotation (det +1: no mirror image of
//     the object), and the signs of axes 1 and 2 are chosen so that the surface's third moment along them
//     (area-weighted over the mesh's faces, about the area centroid) is >= 0; axis 3 follows from det U = +1.
//     `sign_margin` = the smaller |skewness| (third moment / second moment^1.5) of axes 1 and 2: near 0 the sign is
//     decided by noise (a shape symmetric along that axis), and the descriptor of such a shape may flip.
//   * axis order: by σ, so near-equal σ make it arbitrary: `axis_gap` = min(σ1 - σ2, σ2 - σ3) / σ1 (0: two axes of
//     the ellipsoid equal, e.g. a sphere or a rod; the frame about them is then arbitrary).
//   * V may be a reflection when det G < 0 (an orientation-reversing degree-1 map): `parameter_reflected`.
// Translation: the degree-0 coefficient (the parameter mean) is not part of the features. Scale: the coefficients
// are in the mesh's length units; the feature pipeline divides by sqrt(area) or sqrt(xi(1)) when the recipe
// normalises scale.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/mesh/mesh.hpp"
#include "core/sh/sh_descriptor.hpp"

namespace wish {

struct CanonicalShFrame {
  Eigen::MatrixX3d coefficients;   // k x 3 real coefficients (rows j = l² + l + m, columns x', y', z')
  Eigen::Matrix3d object_rotation; // Uᵀ: x' = Uᵀ (x - c)
  Eigen::Matrix3d parameter_rotation;  // V: u = V u'
  Eigen::Vector3d semi_axes;       // σ1 >= σ2 >= σ3: the ellipsoid's semi-axes (length units)
  Eigen::Vector3d skewness;        // along x', y', z' after the sign choice (the first two >= 0)
  double axis_gap = 0;             // see above
  double sign_margin = 0;          // see above
  bool parameter_reflected = false;
};

// Throws InvalidInputError("invalid_descriptor") when the descriptor has Lmax < 1 or a zero degree-1 part.
CanonicalShFrame canonical_sh_frame(const ShDescriptor& descriptor, const Mesh& mesh);

// The feature vector: the canonical real coefficients of degrees l_min..l_max (l_min >= 1), ordered by l, then
// m = -l..l, then x', y', z'; names "csh_<l>_<m>_<x|y|z>" in the same order.
Eigen::VectorXd canonical_sh_features(const Eigen::MatrixX3d& canonical, int l_min, int l_max);
std::vector<std::string> canonical_sh_feature_names(int l_min, int l_max);

}  // namespace wish
