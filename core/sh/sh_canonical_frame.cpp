#include "core/sh/sh_canonical_frame.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/SVD>

#include "core/common/errors.hpp"
#include "core/sh/sh_basis.hpp"
#include "core/sh/sh_conversion.hpp"
#include "core/sh/sh_gram.hpp"

namespace wish {
namespace {

// Area-weighted second and third moments of the surface along each column of `axes`, about the area centroid
// (faces' centroids weighted by their areas: the exact first moment, a midpoint rule for the higher ones).
void surface_moments(const Mesh& mesh, const Eigen::Matrix3d& axes, Eigen::Vector3d& second, Eigen::Vector3d& third) {
  const Eigen::Index F = mesh.face_count();
  Eigen::MatrixX3d centroid(F, 3);
  Eigen::VectorXd area(F);
  for (Eigen::Index f = 0; f < F; ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0)), b = mesh.vertices.row(mesh.faces(f, 1)),
                          c = mesh.vertices.row(mesh.faces(f, 2));
    centroid.row(f) = (a + b + c) / 3;
    area(f) = 0.5 * (b - a).cross(c - a).norm();
  }
  const double total = std::max(area.sum(), 1e-300);
  const Eigen::RowVector3d mean = (area.transpose() * centroid) / total;
  const Eigen::MatrixX3d proj = (centroid.rowwise() - mean) * axes;
  second = (area.transpose() * proj.array().square().matrix()).transpose() / total;
  third = (area.transpose() * proj.array().cube().matrix()).transpose() / total;
}

}  // namespace

CanonicalShFrame canonical_sh_frame(const ShDescriptor& descriptor, const Mesh& mesh) {
  const int L = descriptor.lmax;
  if (L < 1 || descriptor.coefficients.rows() != sh_count(L))
    throw InvalidInputError("invalid_descriptor", "the canonical SH frame needs coefficients of degree >= 1 (Lmax " +
                                                      std::to_string(L) + ")");
  const Eigen::MatrixXd real = complex_to_real_coefficients(descriptor.coefficients);  // k x 3
  const auto basis = ShBasis::get(L);
  // G u = sum_{j of degree 1} a_j S_j(u): S_j is linear in u, its matrix from the basis at the unit vectors.
  Eigen::Matrix3d S1;  // row j - 1, column: direction e_x, e_y, e_z
  for (int d = 0; d < 3; ++d) S1.col(d) = basis->real(Eigen::Vector3d::Unit(d)).segment(1, 3);
  const Eigen::Matrix3d G = real.block(1, 0, 3, 3).transpose() * S1;
  if (!(G.norm() > 0) || !G.allFinite())
    throw InvalidInputError("invalid_descriptor", "the SH surface has no degree-1 part: no first-order ellipsoid to align by");
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(G, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
  const Eigen::Vector3d sigma = svd.singularValues();
  if (U.determinant() < 0) {  // a proper rotation of the object; the pair (u3, v3) flips together
    U.col(2) *= -1;
    V.col(2) *= -1;
  }
  Eigen::Vector3d m2, m3;
  surface_moments(mesh, U, m2, m3);
  for (int i = 0; i < 2; ++i) {
    if (m3(i) < 0) {  // flip axis i and axis 3 together: det U stays +1, G = U Σ Vᵀ unchanged
      U.col(i) *= -1;
      V.col(i) *= -1;
      U.col(2) *= -1;
      V.col(2) *= -1;
      m3(i) = -m3(i);
      m3(2) = -m3(2);
    }
  }
  CanonicalShFrame frame;
  frame.object_rotation = U.transpose();
  frame.parameter_rotation = V;
  frame.parameter_reflected = V.determinant() < 0;
  frame.semi_axes = sigma;  // G u is the degree-1 surface itself (S1 carries the basis normalisation)
  for (int i = 0; i < 3; ++i) frame.skewness(i) = m2(i) > 0 ? m3(i) / std::pow(m2(i), 1.5) : 0.0;
  frame.axis_gap = sigma(0) > 0 ? std::min(sigma(0) - sigma(1), sigma(1) - sigma(2)) / sigma(0) : 0.0;
  frame.sign_margin = std::min(std::abs(frame.skewness(0)), std::abs(frame.skewness(1)));

  // a'_j = ∫ S_j(u') Uᵀ x(V u') du' by an exact product rule: L+1 Gauss-Legendre nodes in cos t (exact to degree
  // 2L+1) times 2L+1 equally spaced azimuths (exact for trigonometric degree <= 2L).
  Eigen::VectorXd z, w;
  gauss_legendre(L + 1, z, w);
  const int np = 2 * L + 1;
  Eigen::MatrixX3d points(z.size() * np, 3), rotated(z.size() * np, 3);
  Eigen::VectorXd weights(z.size() * np);
  for (Eigen::Index i = 0; i < z.size(); ++i) {
    const double s = std::sqrt(std::max(0.0, 1 - z(i) * z(i)));
    for (int p = 0; p < np; ++p) {
      const double phi = 2 * std::numbers::pi * p / np;
      const Eigen::Index q = i * np + p;
      points.row(q) = Eigen::RowVector3d(s * std::cos(phi), s * std::sin(phi), z(i));
      weights(q) = w(i) * 2 * std::numbers::pi / np;
    }
  }
  rotated = points * V.transpose();  // row q: (V u'_q)ᵀ
  const Eigen::MatrixXd values = basis->synthesize(rotated, real) * U;  // x'(u'_q)ᵀ = x(V u')ᵀ U
  frame.coefficients = basis->project(points, weights.asDiagonal() * values);
  return frame;
}

Eigen::VectorXd canonical_sh_features(const Eigen::MatrixX3d& canonical, int l_min, int l_max) {
  const int lmax = sh_lmax_from_count(canonical.rows());
  if (l_min < 1 || l_max < l_min || l_max > lmax)
    throw InvalidInputError("feature_mismatch", "canonical SH features of degrees " + std::to_string(l_min) + ".." +
                                                    std::to_string(l_max) + " from coefficients of Lmax " + std::to_string(lmax));
  Eigen::VectorXd out(3 * (sh_count(l_max) - sh_count(l_min - 1)));
  Eigen::Index i = 0;
  for (int j = sh_count(l_min - 1); j < sh_count(l_max); ++j)
    for (int c = 0; c < 3; ++c) out(i++) = canonical(j, c);
  return out;
}

std::vector<std::string> canonical_sh_feature_names(int l_min, int l_max) {
  std::vector<std::string> names;
  const char* axis[] = {"x", "y", "z"};
  for (int l = l_min; l <= l_max; ++l)
    for (int m = -l; m <= l; ++m)
      for (int c = 0; c < 3; ++c) names.push_back("csh_" + std::to_string(l) + "_" + std::to_string(m) + "_" + axis[c]);
  return names;
}

}  // namespace wish
