#pragma once
// A hard genus-0 test shape shared by the map tests: a tube of radius `wire` (default 0.12) along `turns` (default
// 1.5) turns of a helix (radius 1, pitch 0.8), made by bending a long ellipsoid (icosphere level 4, 2,562 vertices).
#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "core/mesh/icosphere.hpp"

namespace wish::testing {

inline Mesh make_coil(double turns = 1.5, double wire = 0.12) {
  Mesh m = make_icosphere(4);
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i) {
    const Eigen::Vector3d p = m.vertices.row(i).transpose();
    const double t = (p.x() + 1.0) * std::numbers::pi * turns;  // angle along the helix
    const double pitch = 0.8 / (2 * std::numbers::pi);
    const Eigen::Vector3d c(std::cos(t), std::sin(t), pitch * t);
    const Eigen::Vector3d tangent = Eigen::Vector3d(-std::sin(t), std::cos(t), pitch).normalized();
    const Eigen::Vector3d normal(-std::cos(t), -std::sin(t), 0);
    const Eigen::Vector3d binormal = tangent.cross(normal);
    const double r = wire * std::sqrt(std::max(0.0, 1.0 - p.x() * p.x())) /
                     std::max(1e-12, std::sqrt(std::max(1e-24, p.y() * p.y() + p.z() * p.z())));
    m.vertices.row(i) = (c + r * (p.y() * normal + p.z() * binormal)).transpose();
  }
  return m;
}

}  // namespace wish::testing
