#include "core/spherical_map/linear_map.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <unordered_map>
#include <vector>

#include <Eigen/SparseCore>

#include "core/common/elapsed.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/linalg/sparse_cholesky.hpp"

namespace wish::spherical {
namespace {

using Clock = std::chrono::steady_clock;

std::uint64_t pair_key(int i, int j) {
  return (static_cast<std::uint64_t>(std::min(i, j)) << 32) | static_cast<std::uint32_t>(std::max(i, j));
}

std::array<int, 3> rotated_key(int a, int b, int c) {
  std::array<int, 3> key{a, b, c};
  std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
  return key;
}

// Most equilateral face: smallest longest/shortest edge ratio; ties go to the larger face.
template <class Eligible>
Eigen::Index big_triangle(const Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces, Eligible eligible) {
  Eigen::Index best = 0;
  double best_ratio = std::numeric_limits<double>::infinity(), best_len = 0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    if (!eligible(f)) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (int k = 0; k < 3; ++k) {
      const double l = (x.row(faces(f, (k + 1) % 3)) - x.row(faces(f, k))).norm();
      lo = std::min(lo, l);
      hi = std::max(hi, l);
    }
    const double ratio = lo > 0 ? hi / lo : std::numeric_limits<double>::infinity();
    if (ratio < best_ratio * (1 - 1e-9) || (ratio <= best_ratio * (1 + 1e-9) && hi > best_len)) {
      best = f;
      best_ratio = ratio;
      best_len = hi;
    }
  }
  return best;
}

// 1. The puncture: the most equilateral input face that is also a face of the intrinsic triangulation (so that
// removing it from either edge set leaves the same disk).
Eigen::Index puncture_face(const Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces, const geometry::IntrinsicOperator& op) {
  std::set<std::array<int, 3>> intrinsic_faces;
  for (Eigen::Index f = 0; f < op.faces.rows(); ++f) intrinsic_faces.insert(rotated_key(op.faces(f, 0), op.faces(f, 1), op.faces(f, 2)));
  return big_triangle(x, faces, [&](Eigen::Index f) {
    return intrinsic_faces.count(rotated_key(faces(f, 0), faces(f, 1), faces(f, 2))) > 0;
  });
}

// 2. Edge weights without the puncture T's three corners, as (i, j, w) lists: the intrinsic Delaunay weights (all
// ≥ 0, zero ones raised to the floor), and the mesh's own edges with mollified cotangents clamped from below (the
// Tutte/Floater variant, whose embedding guarantee is about the mesh's own faces).
struct PunctureWeights {
  std::vector<geometry::IntrinsicEdgeWeight> intrinsic, clamped;
  long raised = 0;          // intrinsic weights raised to the floor
  long clamped_count = 0;   // own weights raised to the floor
  size_t own_edges = 0;
};

PunctureWeights puncture_weights(const geometry::IntrinsicOperator& op, const Eigen::MatrixX3i& faces, Eigen::Index t,
                                 double min_weight) {
  PunctureWeights w;
  std::unordered_map<std::uint64_t, double> t_part;  // ½ cot of T's corners, per edge of T
  for (int k = 0; k < 3; ++k)
    t_part[pair_key(faces(t, (k + 1) % 3), faces(t, (k + 2) % 3))] += 0.5 * op.input_cotangents(t, k);
  w.intrinsic = op.edges;
  for (auto& e : w.intrinsic)
    if (const auto it = t_part.find(pair_key(e.i, e.j)); it != t_part.end()) e.weight = std::max(0.0, e.weight - it->second);
  std::unordered_map<std::uint64_t, double> own;
  own.reserve(static_cast<size_t>(3 * faces.rows()));
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    if (f == t) continue;
    for (int k = 0; k < 3; ++k)
      own[pair_key(faces(f, (k + 1) % 3), faces(f, (k + 2) % 3))] += 0.5 * op.input_cotangents(f, k);
  }
  double mean_abs = 0;
  for (const auto& [key, weight] : own) mean_abs += std::abs(weight);
  mean_abs = own.empty() ? 1.0 : mean_abs / static_cast<double>(own.size());
  const double w_min = min_weight * mean_abs;
  w.own_edges = own.size();
  w.clamped.reserve(own.size());
  for (const auto& [key, weight] : own) {
    const bool raise = !(weight >= w_min);
    w.clamped_count += raise;
    w.clamped.push_back({static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu), raise ? w_min : weight});
  }
  // Zero intrinsic weights (cocircular quads) are raised too: Tutte needs every weight positive.
  for (auto& e : w.intrinsic)
    if (!(e.weight >= w_min)) {
      e.weight = w_min;
      ++w.raised;
    }
  return w;
}

// The boundary: a planar triangle similar to T = (a, b, c), clockwise, so the disk bounded by a → c → b is CCW;
// translated so that its circumcentre is the origin of the plane.
Eigen::Matrix<double, 3, 2> boundary_triangle(const Eigen::MatrixX3d& x, int a, int b, int c) {
  const double lab = (x.row(b) - x.row(a)).norm(), lac = (x.row(c) - x.row(a)).norm();
  const double cos_a = std::clamp((x.row(b) - x.row(a)).dot(x.row(c) - x.row(a)) / (lab * lac), -1.0, 1.0);
  const double sin_a = std::sqrt(std::max(0.0, 1.0 - cos_a * cos_a));
  Eigen::Matrix<double, 3, 2> zb;
  zb << 0.0, 0.0, lab, 0.0, lac * cos_a, -lac * sin_a;
  const Eigen::Vector2d p = zb.row(1), q = zb.row(2);
  const double d = 2.0 * (p.x() * q.y() - p.y() * q.x());
  const Eigen::Vector2d centre(q.y() * p.squaredNorm() - p.y() * q.squaredNorm(),
                               p.x() * q.squaredNorm() - q.x() * p.squaredNorm());
  for (int k = 0; k < 3; ++k) zb.row(k) -= (centre / d).transpose();
  return zb;
}

// The interior system L_II z_I = −L_IB z_B for any weights, with one Cholesky whose timings go to the step record.
class PlanarHarmonic {
 public:
  PlanarHarmonic(const MapContext& context, int a, int b, int c, const Eigen::Matrix<double, 3, 2>& zb, FlowStepRecord& rec)
      : nv_(context.vertex_count()), a_(a), b_(b), c_(c), zb_(zb), rec_(rec),
        solver_(context.cholesky_options(linalg::CholmodMode::Auto, false)) {
    index_.assign(static_cast<size_t>(nv_), -1);
    for (Eigen::Index i = 0; i < nv_; ++i)
      if (i != a && i != b && i != c) index_[static_cast<size_t>(i)] = ni_++;
  }

  // Harmonic extension of the boundary with edge weights `weights`; false if the system is not definite.
  bool solve(const std::vector<geometry::IntrinsicEdgeWeight>& weights, Eigen::MatrixX2d& z) {
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(2 * weights.size() + static_cast<size_t>(ni_));
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(ni_, 2);
    Eigen::VectorXd diag = Eigen::VectorXd::Zero(ni_);
    for (const auto& e : weights) {
      const int ii = index_[static_cast<size_t>(e.i)], ij = index_[static_cast<size_t>(e.j)];
      if (ii >= 0) diag[ii] += e.weight;
      if (ij >= 0) diag[ij] += e.weight;
      if (ii >= 0 && ij >= 0) {
        triplets.emplace_back(std::max(ii, ij), std::min(ii, ij), -e.weight);  // lower triangle is what is read
      } else if (ii >= 0) {
        rhs.row(ii) += e.weight * zb_.row(slot(e.j));
      } else if (ij >= 0) {
        rhs.row(ij) += e.weight * zb_.row(slot(e.i));
      }
    }
    for (int i = 0; i < ni_; ++i) triplets.emplace_back(i, i, diag[i]);
    Eigen::SparseMatrix<double> system(ni_, ni_);
    system.setFromTriplets(triplets.begin(), triplets.end());
    system.makeCompressed();
    Clock::time_point t0 = Clock::now();
    const bool ok = solver_.factorize(system);
    rec_.factor_seconds += seconds_since(t0);
    if (!ok) return false;
    t0 = Clock::now();
    const Eigen::MatrixXd zi = solver_.solve(rhs);
    rec_.poisson_seconds += seconds_since(t0);
    z.resize(nv_, 2);
    for (Eigen::Index i = 0; i < nv_; ++i) {
      const int k = slot(i);
      z.row(i) = k >= 0 ? Eigen::RowVector2d(zb_.row(k)) : Eigen::RowVector2d(zi.row(index_[static_cast<size_t>(i)]));
    }
    return z.allFinite();
  }

  std::string message() const { return solver_.message(); }

 private:
  int slot(Eigen::Index v) const { return v == a_ ? 0 : v == b_ ? 1 : v == c_ ? 2 : -1; }

  Eigen::Index nv_;
  int a_, b_, c_;
  const Eigen::Matrix<double, 3, 2>& zb_;
  FlowStepRecord& rec_;
  linalg::SparseCholesky solver_;
  std::vector<int> index_;
  int ni_ = 0;
};

// Every face but T counter-clockwise, with a margin of a few ulps relative to its edge lengths.
bool embedded(const Eigen::MatrixX2d& z, const Eigen::MatrixX3i& faces, Eigen::Index t) {
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    if (f == t) continue;
    const Eigen::Vector2d e1 = z.row(faces(f, 1)) - z.row(faces(f, 0)), e2 = z.row(faces(f, 2)) - z.row(faces(f, 0));
    const double det = e1.x() * e2.y() - e1.y() * e2.x();
    if (!(det > 64 * std::numeric_limits<double>::epsilon() * e1.norm() * e2.norm())) return false;
  }
  return true;
}

// 3. Scale to median |z| = 1, inverse stereographic projection (0 ↦ north pole).
Eigen::MatrixX3d inverse_stereographic(Eigen::MatrixX2d z) {
  const Eigen::Index nv = z.rows();
  std::vector<double> radius(static_cast<size_t>(nv));
  for (Eigen::Index i = 0; i < nv; ++i) radius[static_cast<size_t>(i)] = z.row(i).norm();
  std::nth_element(radius.begin(), radius.begin() + nv / 2, radius.end());
  const double median = radius[static_cast<size_t>(nv / 2)];
  if (median > 0) z /= median;
  Eigen::MatrixX3d u(nv, 3);
  for (Eigen::Index i = 0; i < nv; ++i) {
    const double r2 = z.row(i).squaredNorm();
    u.row(i) = Eigen::RowVector3d(2 * z(i, 0), 2 * z(i, 1), 1 - r2) / (1 + r2);
  }
  u.rowwise().normalize();
  return u;
}

}  // namespace

FlowResult linear_map(const MapContext& context, const LinearMapOptions& options, const FlowControl&) {
  const Clock::time_point t_start = Clock::now();
  FlowResult result;
  result.on_sphere = true;
  FlowStepRecord rec;
  rec.step = 1;
  const Eigen::MatrixX3d& x = context.mesh().vertices;
  const Eigen::MatrixX3i& faces = context.faces();
  const Eigen::Index nv = x.rows();
  auto fail = [&](MapCheck check, const std::string& message) {
    result.status = MapStatus::SolverFailed;
    result.failed_check = check;
    result.message = message;
    rec.accepted = false;
    rec.note = message;
    rec.seconds = seconds_since(t_start);
    result.steps.push_back(rec);
    result.vertices = Eigen::MatrixX3d::Constant(nv, 3, std::numeric_limits<double>::quiet_NaN());
    return result;
  };

  const geometry::IntrinsicOperator& op = context.input_operator();
  result.operator_stats = op.stats;
  const Eigen::Index t = puncture_face(x, faces, op);
  const int a = faces(t, 0), b = faces(t, 1), c = faces(t, 2);
  const PunctureWeights weights = puncture_weights(op, faces, t, options.min_weight);
  const Eigen::Matrix<double, 3, 2> zb = boundary_triangle(x, a, b, c);
  PlanarHarmonic plane(context, a, b, c, zb, rec);

  // The intrinsic Delaunay weights give the most conformal map; they are nonnegative, so the planar map of the
  // INTRINSIC triangulation is an embedding, but the mesh's own faces (straight chords between the same vertices)
  // can still fold where edges were flipped. Then the clamped, all-positive weights on the mesh's own edges, whose
  // embedding Tutte/Floater guarantee (clamping costs conformality: cigar K̄ 1.2 → 2.2).
  Eigen::MatrixX2d z;
  std::string weights_used = std::string(geometry::to_string(context.laplacian().kind)) + " cot weights" +
                             (weights.raised > 0 ? " (" + std::to_string(weights.raised) + " raised to the floor)" : "");
  const bool plain_ok = !options.always_clamp && plane.solve(weights.intrinsic, z) && embedded(z, faces, t);
  if (!plain_ok) {
    if (!plane.solve(weights.clamped, z)) return fail(MapCheck::Solver, "linear map: " + plane.message());
    weights_used = std::to_string(weights.clamped_count) + " of " + std::to_string(weights.own_edges) +
                   " mollified cot weights clamped to " + std::to_string(options.min_weight) + " x mean";
    result.clamped_weights = true;
  }
  rec.geometry_seconds = seconds_since(t_start) - rec.factor_seconds - rec.poisson_seconds;
  if (!z.allFinite()) return fail(MapCheck::NonFinite, "linear map: non-finite planar positions");

  result.vertices = inverse_stereographic(std::move(z));
  rec.seconds = seconds_since(t_start);
  result.steps.push_back(rec);
  result.message = "puncture face " + std::to_string(t) + ", " + weights_used;
  return result;
}

}  // namespace wish::spherical
