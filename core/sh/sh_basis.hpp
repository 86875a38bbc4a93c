#pragma once
// Spherical-harmonic basis up to degree Lmax: complex and real, orthonormal on the unit sphere.
//
// Conventions (docs/design/sh-and-invariants.md):
//   * point u = (sin t cos p, sin t sin p, cos t): t = colatitude in [0, pi], p = azimuth.
//   * index of (l, m), m = -l..l:  j = l^2 + l + m (0-based); k = (Lmax+1)^2 functions.
//   * complex  Y_l^m = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!) P_l^m(cos t) e^{i m p}, P_l^m WITH the Condon-Shortley
//     phase (-1)^m (= paper Eq. 7 = scipy.special.sph_harm = Boost.Math spherical_harmonic);
//     Y_l^{-m} = (-1)^m conj(Y_l^m).
//   * real     S_l^0 = Y_l^0;  S_l^m = sqrt2 (-1)^m Re Y_l^m,  S_l^{-m} = sqrt2 (-1)^m Im Y_l^m  (m > 0),
//     i.e. the CS phase is cancelled: S_l^{+-m} = sqrt2 Pbar_l^m(cos t) {cos, sin}(m p) with Pbar >= 0 near t = 0+
//     (S_1^1 = +sqrt(3/(4 pi)) x). Also orthonormal.
// Evaluation uses the fully normalised associated-Legendre recurrences (no factorials): stable and free of
// overflow far beyond l = 100 (tested to 1000). Values below 1e-280 of the sectoral seeds sin^m(t) are flushed to
// zero (avoids denormals near the poles; the flushed values are below 1e-200 in absolute value).
//
// A basis object holds only the recurrence tables of its Lmax; it is immutable, and every member is const and
// thread-safe. ShBasis::get(lmax) returns a shared instance built once per Lmax.

#include <memory>

#include <Eigen/Core>

namespace wish {

inline constexpr int sh_index(int l, int m) { return l * l + l + m; }
inline constexpr int sh_count(int lmax) { return (lmax + 1) * (lmax + 1); }
// Degree l of index j (inverse of sh_index).
int sh_degree(int j);
// Lmax of a coefficient count k = (Lmax+1)^2; throws InvalidInputError when k is not a positive square.
int sh_lmax_from_count(Eigen::Index k);

inline constexpr int kShMaxBasisLmax = 1024;

class ShBasis {
 public:
  // Shared, cached instance (thread-safe). lmax in [0, kShMaxBasisLmax]; throws InvalidInputError otherwise.
  static std::shared_ptr<const ShBasis> get(int lmax);
  explicit ShBasis(int lmax);

  int lmax() const { return lmax_; }
  int size() const { return sh_count(lmax_); }

  // --- one point -------------------------------------------------------------------------------------------
  // Low level: cos t, sin t, cos p, sin p given; writes size() values at out. sin t may be negative (t outside
  // [0, pi]); then the sectoral factor sin^m t keeps its sign (what Boost does).
  void evaluate_real(double cos_t, double sin_t, double cos_p, double sin_p, double* out) const;
  Eigen::VectorXd real(double theta, double phi) const;
  Eigen::VectorXd real(const Eigen::Vector3d& u) const;  // u != 0, need not be normalised
  Eigen::VectorXcd complex(double theta, double phi) const;
  Eigen::VectorXcd complex(const Eigen::Vector3d& u) const;

  // --- many points (rows of an n x 3 matrix of non-zero directions) --------------------------------------------
  // n x k matrix of the real basis, column j = S_j at every point.
  Eigen::MatrixXd real_matrix(const Eigen::MatrixX3d& points) const;
  Eigen::MatrixXcd complex_matrix(const Eigen::MatrixX3d& points) const;
  // Y^T V (k x c) for an n x c matrix V, without forming Y. (V = weights gives the moments sum_i w_i S(u_i).)
  Eigen::MatrixXd project(const Eigen::MatrixX3d& points, const Eigen::MatrixXd& values) const;
  // Y C (n x c) for real coefficients C (k x c), without forming Y.
  Eigen::MatrixXd synthesize(const Eigen::MatrixX3d& points, const Eigen::MatrixXd& coefficients) const;

 private:
  template <class Emit>
  void run_block(int nb, const double* z, const double* s, const double* cp, const double* sp, Emit&& emit) const;
  template <class Emit>
  void run_points(const Eigen::MatrixX3d& points, Eigen::Index begin, Eigen::Index end, Emit&& emit) const;

  int lmax_;
  Eigen::VectorXd a_, b_;     // a_lm, b_lm of Pbar_l^m = a_lm (z Pbar_{l-1}^m - b_lm Pbar_{l-2}^m), index l*(L+1)+m
  Eigen::VectorXd seed_;      // Pbar_m^m = seed_m sin t Pbar_{m-1}^{m-1}
  Eigen::VectorXd first_;     // Pbar_{m+1}^m = first_m z Pbar_m^m
};

}  // namespace wish
