#pragma once
// Quaternion algebra for spin transformations (CPS11 §2; docs/design/spherical-map.md "Notation").
// q = w + x i + y j + z k, Hamilton product (i² = j² = k² = ijk = −1); a vector v ∈ R³ is the imaginary quaternion
// v₁i + v₂j + v₃k, and for imaginary u, v:  u v = −u·v + u×v.
// Real 4×4 form: left multiplication p ↦ q p on coefficient vectors (w, x, y, z) is block(q); block(p)block(q) =
// block(pq) and block(conj q) = block(q)ᵀ, which is what makes the quaternion-Hermitian Dirac matrix a real
// symmetric one.

#include <Eigen/Core>

namespace wish::spherical {

struct Quaternion {
  double w = 0, x = 0, y = 0, z = 0;

  constexpr Quaternion() = default;
  constexpr Quaternion(double w_, double x_, double y_, double z_) : w(w_), x(x_), y(y_), z(z_) {}
  static Quaternion imaginary(const Eigen::Vector3d& v) { return {0.0, v[0], v[1], v[2]}; }
  static constexpr Quaternion real(double a) { return {a, 0.0, 0.0, 0.0}; }

  Eigen::Vector3d vec() const { return {x, y, z}; }
  Eigen::Vector4d coeffs() const { return {w, x, y, z}; }
  Quaternion conj() const { return {w, -x, -y, -z}; }
  double norm2() const { return w * w + x * x + y * y + z * z; }

  friend Quaternion operator*(const Quaternion& a, const Quaternion& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,  //
            a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,  //
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,  //
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
  }
  friend Quaternion operator+(const Quaternion& a, const Quaternion& b) {
    return {a.w + b.w, a.x + b.x, a.y + b.y, a.z + b.z};
  }
  friend Quaternion operator-(const Quaternion& a, const Quaternion& b) {
    return {a.w - b.w, a.x - b.x, a.y - b.y, a.z - b.z};
  }
  friend Quaternion operator*(double s, const Quaternion& q) { return {s * q.w, s * q.x, s * q.y, s * q.z}; }
};

// Matrix of left multiplication by q:  [a −b −c −d; b a −d c; c d a −b; d −c b a]  for q = a + bi + cj + dk.
inline Eigen::Matrix4d left_block(const Quaternion& q) {
  Eigen::Matrix4d m;
  m << q.w, -q.x, -q.y, -q.z,  //
      q.x, q.w, -q.z, q.y,     //
      q.y, q.z, q.w, -q.x,     //
      q.z, -q.y, q.x, q.w;
  return m;
}

}  // namespace wish::spherical
