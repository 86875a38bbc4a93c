#include "core/synth/nucleus_shape.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "core/common/errors.hpp"
#include "core/synth/synth_random.hpp"

namespace wish::synth {
namespace {

// Per-class ranges. Sizes: the paper's nuclei have an oriented-bounding-box diagonal of 11.26 +- 2.26 µm;
// shapes follow the usual EM descriptions: neurons large, round, smooth, sometimes one deep fold; astrocytes
// oval, slightly irregular; endothelial nuclei long, flat and curved along the vessel; microglia small,
// elongated, bean-shaped and lobulated with clefts; pericytes flat, bent around the capillary, bean-like;
// oligodendrocytes small, round, with a lumpy heterochromatic outline.
struct ClassRanges {
  double a, a_sd;            // long semi-axis (µm), relative sd
  double ba, ca;             // b/a, c/b
  double bend;               // curvature * a (radians over half the length)
  int lobes; double lobe_amp;
  int invag_min, invag_max; double invag_depth;
  double roughness;          // amplitude of many small bumps
};

const ClassRanges kRanges[6] = {
    /* neuron          */ {4.3, 0.08, 0.90, 0.88, 0.00, 0, 0.00, 0, 1, 0.30, 0.010},
    /* astrocyte       */ {3.7, 0.08, 0.80, 0.80, 0.00, 2, 0.08, 0, 1, 0.15, 0.025},
    /* endothelium     */ {5.6, 0.08, 0.55, 0.45, 0.55, 1, 0.05, 0, 1, 0.10, 0.015},
    /* microglia       */ {3.5, 0.08, 0.60, 0.75, 0.30, 3, 0.15, 1, 2, 0.30, 0.035},
    /* pericyte        */ {4.2, 0.08, 0.55, 0.55, 0.75, 2, 0.10, 0, 1, 0.25, 0.025},
    /* oligodendrocyte */ {2.9, 0.08, 0.90, 0.85, 0.00, 1, 0.05, 0, 0, 0.00, 0.050},
};

Eigen::Vector3d random_unit(Random& r) {
  for (;;) {
    Eigen::Vector3d v(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1));
    const double n = v.norm();
    if (n > 1e-3 && n <= 1) return v / n;
  }
}

}  // namespace

const std::vector<std::string>& demo_classes() {
  static const std::vector<std::string> names = {"neuron",   "astrocyte", "endothelium",
                                                 "microglia", "pericyte",  "oligodendrocyte"};
  return names;
}

double NucleusShape::radius_factor(const Eigen::Vector3d& u) const {
  double f = 1;
  for (const Bump& bump : bumps) f += bump.amplitude * std::exp(-(1 - u.dot(bump.direction)) / bump.width);
  return std::max(f, 0.25);
}

bool NucleusShape::inside(const Eigen::Vector3d& world) const {
  Eigen::Vector3d q = rotation.transpose() * (world - centre);
  if (bend > 0) {  // undo the bend: the straight shape's x axis was wrapped onto a circle of radius 1/bend
    const double R = 1 / bend;
    const double r = std::hypot(q.x(), R - q.z());
    const double theta = std::atan2(q.x(), R - q.z());
    q = Eigen::Vector3d(theta * R, q.y(), R - r);
  }
  const Eigen::Vector3d n(q.x() / a, q.y() / b, q.z() / c);
  const double rho = n.norm();
  if (rho < 1e-12) return true;
  return rho < radius_factor(n / rho);
}

double NucleusShape::bounding_radius() const {
  double amp = 1;
  for (const Bump& bump : bumps) amp += std::max(bump.amplitude, 0.0);
  return a * amp * 1.05 + 0.5;
}

NucleusShape sample_nucleus_shape(int class_index, std::uint64_t seed) {
  if (class_index < 0 || class_index >= 6) throw InvalidInputError("invalid_parameter", "unknown demo class index");
  const ClassRanges& k = kRanges[class_index];
  Random r(seed);
  NucleusShape s;
  s.a = k.a * std::exp(k.a_sd * r.normal());
  s.b = s.a * std::clamp(k.ba * std::exp(0.06 * r.normal()), 0.3, 1.0);
  s.c = s.b * std::clamp(k.ca * std::exp(0.06 * r.normal()), 0.3, 1.0);
  s.bend = k.bend > 0 ? std::max(0.0, k.bend * (1 + 0.2 * r.normal())) / s.a : 0;
  for (int i = 0; i < k.lobes; ++i)
    s.bumps.push_back({random_unit(r), k.lobe_amp * r.uniform(0.6, 1.4), r.uniform(0.15, 0.35)});
  const int invaginations = k.invag_min + r.below(k.invag_max - k.invag_min + 1);
  for (int i = 0; i < invaginations; ++i)
    s.bumps.push_back({random_unit(r), -k.invag_depth * r.uniform(0.7, 1.3), r.uniform(0.03, 0.07)});
  for (int i = 0; i < 40; ++i)
    s.bumps.push_back({random_unit(r), k.roughness * r.uniform(-1, 1), r.uniform(0.01, 0.03)});
  // Uniform random rotation from a random unit quaternion.
  Eigen::Quaterniond q(r.normal(), r.normal(), r.normal(), r.normal());
  q.normalize();
  s.rotation = q.toRotationMatrix();
  s.centre = Eigen::Vector3d(r.uniform(-50, 50), r.uniform(-50, 50), r.uniform(-50, 50));
  return s;
}

}  // namespace wish::synth
