#include "core/spherical_map/map_verification.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>

namespace wish::spherical {
namespace {

// Triangle (p0, p1, p2) in its own orthonormal 2D frame: columns are p1 − p0 and p2 − p0.
Eigen::Matrix2d local_frame(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2) {
  const Eigen::Vector3d e1 = p1 - p0, e2 = p2 - p0;
  const double l1 = e1.norm();
  const Eigen::Vector3d x = e1 / l1;
  const Eigen::Vector3d n = e1.cross(e2);
  const Eigen::Vector3d y = n.normalized().cross(x);
  Eigen::Matrix2d m;
  m << l1, e2.dot(x), 0.0, e2.dot(y);
  return m;
}

}  // namespace

FaceDistortion face_distortion(const Eigen::MatrixX3d& input_vertices, const Eigen::MatrixX3i& faces,
                               const Eigen::MatrixX3d& sphere) {
  const Eigen::Index nf = faces.rows();
  FaceDistortion d;
  d.conformal.resize(nf);
  d.area_ratio.resize(nf);
  d.input_area.resize(nf);
  Eigen::VectorXd& in_area = d.input_area;
  Eigen::VectorXd out_area(nf);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = sphere.row(faces(f, 0)), b = sphere.row(faces(f, 1)), c = sphere.row(faces(f, 2));
    const Eigen::Vector3d p0 = input_vertices.row(faces(f, 0)), p1 = input_vertices.row(faces(f, 1)),
                          p2 = input_vertices.row(faces(f, 2));
    in_area[f] = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    out_area[f] = 0.5 * (b - a).cross(c - a).norm();
    const Eigen::Matrix2d j = local_frame(a, b, c) * local_frame(p0, p1, p2).inverse();
    // Singular values of a 2×2 matrix: σ₁,₂ = (√(‖J‖²_F + 2|det J|) ± √(‖J‖²_F − 2|det J|)) / 2.
    const double fro2 = j.squaredNorm(), det = std::abs(j.determinant());
    const double sp = std::sqrt(std::max(0.0, fro2 + 2 * det)), sm = std::sqrt(std::max(0.0, fro2 - 2 * det));
    const double s1 = 0.5 * (sp + sm), s2 = 0.5 * (sp - sm);
    double kf = s2 > 0 ? s1 / s2 : std::numeric_limits<double>::infinity();
    if (!std::isfinite(kf)) kf = std::numeric_limits<double>::infinity();
    d.conformal[f] = kf;
  }
  const double input_area = in_area.sum(), sphere_area = out_area.sum();
  for (Eigen::Index f = 0; f < nf; ++f) d.area_ratio[f] = (out_area[f] / sphere_area) / (in_area[f] / input_area);
  return d;
}

bool is_bad_sphere_face(const Eigen::MatrixX3d& u, const Eigen::MatrixX3i& faces, Eigen::Index f, double min_height) {
  const Eigen::Vector3d a = u.row(faces(f, 0)), b = u.row(faces(f, 1)), c = u.row(faces(f, 2));
  const Eigen::Vector3d n = (b - a).cross(c - a);
  if (!(n.dot(a + b + c) > 0)) return true;
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  return !(n.norm() >= min_height * longest);
}

long count_bad_sphere_faces(const Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces, double min_height) {
  long bad = 0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) bad += is_bad_sphere_face(sphere, faces, f, min_height);
  return bad;
}

namespace {

// The smallest corner angle of input face f, in degrees.
double smallest_corner_degrees(const Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces, Eigen::Index f) {
  double least = 180;
  for (int c = 0; c < 3; ++c) {
    const Eigen::Vector3d p = x.row(faces(f, c)), u = x.row(faces(f, (c + 1) % 3)) - p.transpose(),
                          w = x.row(faces(f, (c + 2) % 3)) - p.transpose();
    least = std::min(least, std::atan2(u.cross(w).norm(), u.dot(w)) * 180.0 / std::numbers::pi);
  }
  return least;
}

// The 99th percentile, nearest rank (conformal_p99 and its well-shaped share); reorders v.
double percentile_99(std::vector<double>& v) {
  const size_t idx = std::min(v.size() - 1, static_cast<size_t>(std::ceil(0.99 * static_cast<double>(v.size()))) - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(idx), v.end());
  return v[idx];
}

}  // namespace

MapQuality measure_map(const Eigen::MatrixX3d& input_vertices, const Eigen::MatrixX3i& faces,
                       const Eigen::MatrixX3d& sphere, const MapVerificationThresholds& thresholds) {
  MapQuality q;
  for (Eigen::Index i = 0; i < sphere.rows(); ++i)
    if (!sphere.row(i).allFinite()) ++q.non_finite_vertices;
  const Eigen::Index nf = faces.rows();
  double solid_angle = 0;
  q.min_face_area = q.min_face_height = std::numeric_limits<double>::infinity();
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = sphere.row(faces(f, 0)), b = sphere.row(faces(f, 1)), c = sphere.row(faces(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (!(n.dot(a + b + c) > 0)) ++q.flipped_faces;
    const double area = 0.5 * n.norm();
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const double height = longest > 0 ? 2.0 * area / longest : 0.0;
    q.min_face_area = std::min(q.min_face_area, area);
    q.min_face_height = std::min(q.min_face_height, height);
    if (!(height >= thresholds.degenerate_height) || !(area >= thresholds.degenerate_area * 4.0 * std::numbers::pi))
      ++q.degenerate_faces;
    const double num = a.dot(b.cross(c));
    const double den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
    solid_angle += 2.0 * std::atan2(num, den);
  }
  q.degree = static_cast<int>(std::lround(solid_angle / (4.0 * std::numbers::pi)));
  // Conformal distortion and area distortion, from the per-face figures. Faces of (near) zero input area — a real
  // segmentation mesh's twin-vertex faces — have no meaningful K or area ratio: they are counted, not averaged.
  const FaceDistortion d = face_distortion(input_vertices, faces, sphere);
  const double input_area = d.input_area.sum();
  std::vector<double> k, k_well_shaped;
  k.reserve(static_cast<size_t>(nf));
  k_well_shaped.reserve(static_cast<size_t>(nf));
  double ksum = 0, log_sum = 0;
  const double min_input_area = 1e-14 * input_area / static_cast<double>(std::max<Eigen::Index>(1, nf));
  for (Eigen::Index f = 0; f < nf; ++f) {
    if (!(d.input_area[f] > min_input_area)) {
      ++q.skipped_input_faces;
      continue;
    }
    k.push_back(d.conformal[f]);
    if (smallest_corner_degrees(input_vertices, faces, f) >= kWellShapedDegrees) k_well_shaped.push_back(d.conformal[f]);
    ksum += d.conformal[f];
    log_sum += std::abs(std::log(d.area_ratio[f]));
  }
  if (!k.empty()) {
    q.conformal_mean = ksum / static_cast<double>(k.size());
    q.conformal_max = *std::max_element(k.begin(), k.end());
    q.conformal_p99 = percentile_99(k);
    q.conformal_p99_well_shaped = k_well_shaped.empty() ? q.conformal_p99 : percentile_99(k_well_shaped);
    q.area_distortion = std::exp(log_sum / static_cast<double>(k.size()));
  }
  const bool bijective = q.non_finite_vertices == 0 && q.flipped_faces == 0 && q.degenerate_faces == 0 && q.degree == 1;
  q.verdict = !bijective ? MapVerdict::Failed
              : q.conformal_p99 <= thresholds.max_conformal_p99 ? MapVerdict::Good
                                                                : MapVerdict::Distorted;
  return q;
}

MapCheck failed_map_check(const MapQuality& quality, const MapVerificationThresholds& thresholds) {
  if (quality.non_finite_vertices > 0) return MapCheck::NonFinite;
  if (quality.flipped_faces > 0) return MapCheck::FlippedFaces;
  if (quality.degenerate_faces > 0) return MapCheck::DegenerateFaces;
  if (quality.degree != 1) return MapCheck::Degree;
  if (thresholds.strict_conformal_bound && !(quality.conformal_p99 <= thresholds.max_conformal_p99))
    return MapCheck::ConformalDistortion;
  return MapCheck::None;
}

}  // namespace wish::spherical
