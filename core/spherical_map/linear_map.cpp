#include "core/spherical_map/linear_map.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/SparseCore>

#include "core/geometry/face_geometry.hpp"
#include "core/geometry/vertex_pattern.hpp"
#include "core/linalg/sparse_cholesky.hpp"

namespace wish::spherical {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Most equilateral face: smallest longest/shortest edge ratio; ties go to the larger face.
Eigen::Index big_triangle(const Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces) {
  Eigen::Index best = 0;
  double best_ratio = std::numeric_limits<double>::infinity(), best_len = 0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
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

}  // namespace

FlowResult linear_map(const Mesh& mesh, const LinearMapOptions& options, LinearSolverKind solver_kind) {
  const Clock::time_point t_start = Clock::now();
  FlowResult result;
  result.on_sphere = true;
  FlowStepRecord rec;
  rec.step = 1;
  const Eigen::MatrixX3d& x = mesh.vertices;
  const Eigen::MatrixX3i& faces = mesh.faces;
  const Eigen::Index nv = x.rows();
  auto fail = [&](const std::string& check, const std::string& message) {
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

  // 1. The puncture.
  const Eigen::Index t = big_triangle(x, faces);
  const int a = faces(t, 0), b = faces(t, 1), c = faces(t, 2);

  // 2. Edge weights ½(cot α + cot β) of the mesh without T, on the vertex pattern, clamped from below.
  const geometry::VertexPattern pattern = geometry::build_vertex_pattern(nv, faces);
  const Eigen::MatrixX3d cot = geometry::corner_cotangents(x, faces);
  std::vector<double> w(static_cast<size_t>(pattern.pattern.nonZeros()), 0.0);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    if (f == t) continue;
    const auto& slot = pattern.slot[static_cast<size_t>(f)];
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      const double half_cot = 0.5 * cot(f, k);
      w[static_cast<size_t>(slot[static_cast<size_t>(3 * i + j)])] += half_cot;
      w[static_cast<size_t>(slot[static_cast<size_t>(3 * j + i)])] += half_cot;
    }
  }
  double mean_abs = 0;
  long count = 0;
  for (Eigen::Index col = 0; col < nv; ++col)
    for (int p = pattern.pattern.outerIndexPtr()[col]; p < pattern.pattern.outerIndexPtr()[col + 1]; ++p)
      if (pattern.pattern.innerIndexPtr()[p] != col && std::isfinite(w[static_cast<size_t>(p)])) {
        mean_abs += std::abs(w[static_cast<size_t>(p)]);
        ++count;
      }
  mean_abs = count > 0 ? mean_abs / static_cast<double>(count) : 1.0;
  const double w_min = options.min_weight * mean_abs;
  std::vector<double> w_clamped = w;
  long clamped = 0;
  for (Eigen::Index col = 0; col < nv; ++col)
    for (int p = pattern.pattern.outerIndexPtr()[col]; p < pattern.pattern.outerIndexPtr()[col + 1]; ++p) {
      if (pattern.pattern.innerIndexPtr()[p] == col) continue;
      double& wp = w_clamped[static_cast<size_t>(p)];
      if (!std::isfinite(w[static_cast<size_t>(p)])) w[static_cast<size_t>(p)] = w_min;  // degenerate input corner
      if (!(wp >= w_min)) {
        wp = w_min;
        ++clamped;
      }
    }

  // Boundary: a planar triangle similar to T, clockwise (a, b, c), so the disk bounded by a → c → b is CCW.
  const double lab = (x.row(b) - x.row(a)).norm(), lac = (x.row(c) - x.row(a)).norm();
  const double cos_a = std::clamp((x.row(b) - x.row(a)).dot(x.row(c) - x.row(a)) / (lab * lac), -1.0, 1.0);
  const double sin_a = std::sqrt(std::max(0.0, 1.0 - cos_a * cos_a));
  Eigen::Matrix<double, 3, 2> zb;
  zb << 0.0, 0.0, lab, 0.0, lac * cos_a, -lac * sin_a;
  // Circumcentre of the boundary triangle (becomes the origin of the plane).
  Eigen::Vector2d centre;
  {
    const Eigen::Vector2d p = zb.row(1), q = zb.row(2);
    const double d = 2.0 * (p.x() * q.y() - p.y() * q.x());
    centre = Eigen::Vector2d(q.y() * p.squaredNorm() - p.y() * q.squaredNorm(),
                             p.x() * q.squaredNorm() - q.x() * p.squaredNorm()) / d;
  }
  for (int k = 0; k < 3; ++k) zb.row(k) -= centre.transpose();

  // Interior system L_II z_I = −L_IB z_B.
  std::vector<int> index(static_cast<size_t>(nv), -1);
  int ni = 0;
  for (Eigen::Index i = 0; i < nv; ++i)
    if (i != a && i != b && i != c) index[static_cast<size_t>(i)] = ni++;
  auto boundary_slot = [&](Eigen::Index v) { return v == a ? 0 : v == b ? 1 : v == c ? 2 : -1; };
  linalg::CholeskyOptions copt;
  copt.backend = solver_kind == LinearSolverKind::Cholmod ? linalg::CholeskyBackend::Cholmod
                                                          : linalg::CholeskyBackend::EigenSimplicial;
  linalg::SparseCholesky solver(copt);
  // Harmonic extension of the boundary with edge weights `weights`; false if the system is not definite.
  auto solve_plane = [&](const std::vector<double>& weights, Eigen::MatrixX2d& z) {
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(static_cast<size_t>(pattern.pattern.nonZeros()));
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(ni, 2);
    for (Eigen::Index col = 0; col < nv; ++col) {
      const int jc = index[static_cast<size_t>(col)];
      if (jc < 0) continue;
      double diag = 0;
      for (int p = pattern.pattern.outerIndexPtr()[col]; p < pattern.pattern.outerIndexPtr()[col + 1]; ++p) {
        const int row = pattern.pattern.innerIndexPtr()[p];
        if (row == col) continue;
        const double wp = weights[static_cast<size_t>(p)];
        diag += wp;
        const int ir = index[static_cast<size_t>(row)];
        if (ir >= 0) {
          if (ir >= jc) triplets.emplace_back(ir, jc, -wp);  // lower triangle is what the Cholesky reads
        } else {
          rhs.row(jc) += wp * zb.row(boundary_slot(row));
        }
      }
      triplets.emplace_back(jc, jc, diag);
    }
    Eigen::SparseMatrix<double> system(ni, ni);
    system.setFromTriplets(triplets.begin(), triplets.end());
    system.makeCompressed();
    Clock::time_point t0 = Clock::now();
    const bool ok = solver.factorize(system);
    rec.factor_seconds += seconds_since(t0);
    if (!ok) return false;
    t0 = Clock::now();
    const Eigen::MatrixXd zi = solver.solve(rhs);
    rec.poisson_seconds += seconds_since(t0);
    z.resize(nv, 2);
    for (Eigen::Index i = 0; i < nv; ++i) {
      const int k = boundary_slot(i);
      z.row(i) = k >= 0 ? Eigen::RowVector2d(zb.row(k)) : Eigen::RowVector2d(zi.row(index[static_cast<size_t>(i)]));
    }
    return z.allFinite();
  };
  // Every face but T counter-clockwise, with a margin of a few ulps relative to its edge lengths.
  auto embedded = [&](const Eigen::MatrixX2d& z) {
    for (Eigen::Index f = 0; f < faces.rows(); ++f) {
      if (f == t) continue;
      const Eigen::Vector2d e1 = z.row(faces(f, 1)) - z.row(faces(f, 0)), e2 = z.row(faces(f, 2)) - z.row(faces(f, 0));
      const double det = e1.x() * e2.y() - e1.y() * e2.x();
      if (!(det > 64 * std::numeric_limits<double>::epsilon() * e1.norm() * e2.norm())) return false;
    }
    return true;
  };
  // The plain cot weights give the most conformal map (clamping costs conformality: cigar K̄ 1.2 → 2.2), but
  // negative weights can fold it; then the clamped, all-positive weights, whose embedding Tutte/Floater guarantee.
  Eigen::MatrixX2d z;
  std::string weights_used = "cot weights";
  const bool plain_ok = (clamped == 0 || !options.always_clamp) && solve_plane(w, z) && (clamped == 0 || embedded(z));
  if (!plain_ok) {
    if (clamped == 0 || !solve_plane(w_clamped, z)) return fail("solver", "linear map: " + solver.message());
    weights_used = std::to_string(clamped / 2) + " of " + std::to_string(pattern.edge_count) +
                   " cot weights clamped to " + std::to_string(options.min_weight) + " x mean";
  }
  rec.geometry_seconds = seconds_since(t_start) - rec.factor_seconds - rec.poisson_seconds;
  if (!z.allFinite()) return fail("non_finite", "linear map: non-finite planar positions");

  // 3. Scale to median |z| = 1, inverse stereographic projection.
  std::vector<double> radius(static_cast<size_t>(nv));
  for (Eigen::Index i = 0; i < nv; ++i) radius[static_cast<size_t>(i)] = z.row(i).norm();
  std::nth_element(radius.begin(), radius.begin() + nv / 2, radius.end());
  const double median = radius[static_cast<size_t>(nv / 2)];
  if (median > 0) z /= median;
  result.vertices.resize(nv, 3);
  for (Eigen::Index i = 0; i < nv; ++i) {
    const double r2 = z.row(i).squaredNorm();
    result.vertices.row(i) = Eigen::RowVector3d(2 * z(i, 0), 2 * z(i, 1), 1 - r2) / (1 + r2);
  }
  result.vertices.rowwise().normalize();
  rec.seconds = seconds_since(t_start);
  result.steps.push_back(rec);
  result.message = "puncture face " + std::to_string(t) + ", " + weights_used;
  return result;
}

}  // namespace wish::spherical
