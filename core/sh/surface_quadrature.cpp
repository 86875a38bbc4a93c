#include "core/sh/surface_quadrature.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace wish {

SurfaceSamples surface_quadrature(const Mesh& input, const Eigen::MatrixX3d& sphere, int lmax) {
  const Eigen::MatrixX3i& faces = input.faces;
  const double spacing = kMaxSampleSpacing / (lmax + 1.0);
  // Splits per face first, to size the output once.
  std::vector<int> splits(static_cast<size_t>(faces.rows()));
  Eigen::Index count = 0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    double longest = 0;
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (sphere.row(faces(f, k)) - sphere.row(faces(f, (k + 1) % 3))).norm());
    const int m = std::clamp(static_cast<int>(std::ceil(longest / spacing)), 1, kMaxFaceSplits);
    splits[static_cast<size_t>(f)] = m;
    count += 3 * Eigen::Index{m} * m;
  }
  SurfaceSamples s;
  s.sphere_points.resize(count, 3);
  s.targets.resize(count, 3);
  s.weights.resize(count);
  Eigen::Index n = 0;
  const auto emit = [&](const Eigen::Matrix3d& x, const Eigen::Matrix3d& u, const Eigen::Vector3d& b0,
                        const Eigen::Vector3d& b1, const Eigen::Vector3d& b2, double weight) {
    // The 3-point degree-2 rule on the sub-triangle with face-barycentric corners b0, b1, b2.
    static constexpr std::array<std::array<double, 3>, 3> kRule{{{2.0 / 3, 1.0 / 6, 1.0 / 6},
                                                                 {1.0 / 6, 2.0 / 3, 1.0 / 6},
                                                                 {1.0 / 6, 1.0 / 6, 2.0 / 3}}};
    for (const auto& r : kRule) {
      const Eigen::Vector3d b = r[0] * b0 + r[1] * b1 + r[2] * b2;
      s.targets.row(n) = (x * b).transpose();
      s.sphere_points.row(n) = (u * b).normalized().transpose();
      s.weights(n) = weight / 3.0;
      ++n;
    }
  };
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    Eigen::Matrix3d x, u;  // columns: the face's corners
    for (int k = 0; k < 3; ++k) {
      x.col(k) = input.vertices.row(faces(f, k)).transpose();
      u.col(k) = sphere.row(faces(f, k)).transpose();
    }
    const double area = 0.5 * (x.col(1) - x.col(0)).cross(x.col(2) - x.col(0)).norm();
    const int m = splits[static_cast<size_t>(f)];
    const double sub_area = area / (double(m) * m);
    const auto corner = [m](int i, int j) {  // barycentric of grid point (i, j): weights of corners 0, 1, 2
      return Eigen::Vector3d(1.0 - double(i + j) / m, double(i) / m, double(j) / m);
    };
    for (int i = 0; i < m; ++i)
      for (int j = 0; i + j < m; ++j) {
        emit(x, u, corner(i, j), corner(i + 1, j), corner(i, j + 1), sub_area);
        if (i + j + 1 < m) emit(x, u, corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1), sub_area);
      }
  }
  return s;
}

}  // namespace wish
