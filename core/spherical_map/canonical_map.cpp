// The canonical map's projected Newton relaxation (see the header for the definition and the method).
#include "core/spherical_map/canonical_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include "core/common/cpu_budget.hpp"
#include "core/common/enum_names.hpp"
#include "core/common/errors.hpp"
#include "core/linalg/sparse_cholesky.hpp"
#include "core/spherical_map/map_verification.hpp"

namespace wish {

inline constexpr EnumNames<CanonicalMap, 2> kCanonicalMapNames{{{
    {CanonicalMap::None, "none"}, {CanonicalMap::Isometric, "isometric"}}}};
inline constexpr EnumNames<CanonicalMapStop, 7> kCanonicalMapStopNames{{{
    {CanonicalMapStop::NotRun, "not_run"},
    {CanonicalMapStop::Converged, "converged"},
    {CanonicalMapStop::IterationCap, "iteration_cap"},
    {CanonicalMapStop::TimeBudget, "time_budget"},
    {CanonicalMapStop::LineSearchFailed, "line_search_failed"},
    {CanonicalMapStop::SolverFailed, "solver_failed"},
    {CanonicalMapStop::Reverted, "reverted"}}}};

const char* to_string(CanonicalMap method) { return kCanonicalMapNames.name(method); }
CanonicalMap canonical_map_from_name(const std::string& name) {
  return kCanonicalMapNames.parse(name, "canonical map", "canonical");
}
const char* to_string(CanonicalMapStop stop) { return kCanonicalMapStopNames.name(stop); }

}  // namespace wish

namespace wish::spherical {
// Named, not anonymous: the area is compiled in unity batches (cmake/WishBuildSpeed.cmake), where file-local helpers
// of different files share one translation unit.
namespace canonical_map_detail {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Levenberg–Marquardt damping, relative to the Hessian's mean diagonal.
constexpr double kInitialDamping = 1e-6, kMinimalDamping = 1e-10, kMaximalDamping = 1e2;

// Per input face: the inverse of its reference edge matrix Dm = [c₁ − c₀, c₂ − c₀] (the triangle laid out in its
// plane from mollified lengths, scaled so that the surface's total area is 4π) and its area share w_f.
struct ReferenceTriangles {
  std::vector<Eigen::Matrix2d> inverse_shape;
  Eigen::VectorXd weight;
};

ReferenceTriangles reference_triangles(const Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces, double delta) {
  const Eigen::Index nf = faces.rows();
  Eigen::MatrixX3d lengths(nf, 3);  // column k: the side opposite corner k
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      lengths(f, k) = (x.row(faces(f, (k + 1) % 3)) - x.row(faces(f, (k + 2) % 3))).norm();
  // Intrinsic mollification (Sharp & Crane 2020; intrinsic_laplacian.hpp): one ε for every side, so that every
  // triangle inequality holds with margin δ·mean side.
  const double margin = nf > 0 ? delta * lengths.mean() : 0.0;
  double epsilon = 0;
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      epsilon = std::max(epsilon, margin - (lengths(f, (k + 1) % 3) + lengths(f, (k + 2) % 3) - lengths(f, k)));
  lengths.array() += epsilon;

  ReferenceTriangles ref;
  ref.inverse_shape.resize(static_cast<size_t>(nf));
  ref.weight.resize(nf);
  std::vector<Eigen::Matrix2d> shape(static_cast<size_t>(nf));
  for (Eigen::Index f = 0; f < nf; ++f) {
    const double l0 = lengths(f, 0), l1 = lengths(f, 1), l2 = lengths(f, 2);
    // c₀ = 0, c₁ = (l₂, 0) (side c₀c₁ is opposite corner 2), c₂ at distance l₁ from c₀ and l₀ from c₁.
    const double cx = (l2 * l2 + l1 * l1 - l0 * l0) / (2.0 * l2);
    const double cy = std::sqrt(std::max(0.0, l1 * l1 - cx * cx));
    Eigen::Matrix2d dm;
    dm << l2, cx, 0.0, cy;
    shape[static_cast<size_t>(f)] = dm;
    ref.weight(f) = 0.5 * l2 * cy;
  }
  const double total = ref.weight.sum();
  if (!(total > 0) || !std::isfinite(total))
    throw InvalidInputError("degenerate_mesh", "the mesh has zero total area; the canonical map is undefined",
                            {{"area", total}});
  const double scale = std::sqrt(4.0 * std::numbers::pi / total);  // lengths × scale: total area 4π
  for (Eigen::Index f = 0; f < nf; ++f) ref.inverse_shape[static_cast<size_t>(f)] = (scale * shape[static_cast<size_t>(f)]).inverse();
  ref.weight /= total;
  return ref;
}

// Face f on the sphere, projected to the plane through its centroid direction m = (p₀ + p₁ + p₂)/‖·‖: E = [b₁ b₂]
// (3×2 orthonormal, ⟂ m, b₁ along the projection of p₁ − p₀, b₁ × b₂ = m) and Ds = the local coordinates of
// p₁ − p₀, p₂ − p₀. Projected, not the chord triangle in its own plane: three points on one great circle span a chord
// triangle of positive area whose plane contains the origin (a collapsed spherical triangle: the verification's
// n·(p₀+p₁+p₂) > 0 fails); projected onto ⟂ m it has area → 0, so the energy's det F barrier sees the collapse
// (measured: the chord form let steps of 1e-8 flip such faces on a real spine). Derivatives treat m as fixed: m's
// rotation changes the projection only by O((m·e)/‖e‖) = O(edge length) relative. False when the projected
// triangle is flipped or the face is numerically degenerate (is_bad_sphere_face).
struct ChordFrame {
  Eigen::Matrix<double, 3, 2> axes;
  Eigen::Matrix2d shape;
};

bool chord_frame(const Eigen::MatrixX3d& u, const Eigen::MatrixX3i& faces, Eigen::Index f, double min_height,
                 ChordFrame& frame) {
  if (is_bad_sphere_face(u, faces, f, min_height)) return false;
  const Eigen::Vector3d p0 = u.row(faces(f, 0)), p1 = u.row(faces(f, 1)), p2 = u.row(faces(f, 2));
  const Eigen::Vector3d m = (p0 + p1 + p2).normalized();
  const Eigen::Vector3d e1 = p1 - p0, e2 = p2 - p0;
  const Eigen::Vector3d b1 = (e1 - e1.dot(m) * m).normalized();
  const Eigen::Vector3d b2 = m.cross(b1);
  frame.axes.col(0) = b1;
  frame.axes.col(1) = b2;
  frame.shape << e1.dot(b1), e2.dot(b1), 0.0, e2.dot(b2);
  return frame.shape(1, 1) > 0;
}

// An orthonormal basis of the tangent plane at each sphere point (3×2 per vertex).
std::vector<Eigen::Matrix<double, 3, 2>> tangent_bases(const Eigen::MatrixX3d& u) {
  std::vector<Eigen::Matrix<double, 3, 2>> bases(static_cast<size_t>(u.rows()));
  for (Eigen::Index i = 0; i < u.rows(); ++i) {
    const Eigen::Vector3d n = u.row(i);
    Eigen::Index axis = 0;
    n.cwiseAbs().minCoeff(&axis);
    const Eigen::Vector3d t1 = n.cross(Eigen::Vector3d::Unit(axis)).normalized();
    bases[static_cast<size_t>(i)].col(0) = t1;
    bases[static_cast<size_t>(i)].col(1) = n.cross(t1);
  }
  return bases;
}

class Relaxation {
 public:
  Relaxation(const Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces, const CanonicalMapOptions& options,
             double min_height)
      : faces_(faces), options_(options), min_height_(min_height),
        reference_(reference_triangles(x, faces, options.mollify_delta)) {}

  double energy(const Eigen::MatrixX3d& u) const {
    const std::vector<Eigen::Matrix2d>& inverse_shape = reference_.inverse_shape;
    double e = 0;
    ChordFrame frame;
    for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
      if (!chord_frame(u, faces_, f, min_height_, frame)) return kInfinity;
      const double psi = options_.energy.value(frame.shape * inverse_shape[static_cast<size_t>(f)]);
      if (!std::isfinite(psi)) return kInfinity;
      e += reference_.weight(f) * psi;
    }
    return e;
  }

  CanonicalMapReport run(Eigen::MatrixX3d& u, const Deadline& deadline) {
    const double cpu0 = CpuBudget::thread_cpu_seconds();
    CanonicalMapReport report;
    report.method = CanonicalMap::Isometric;
    const double scale = std::max(1.0, static_cast<double>(u.rows()) / 10000.0);
    const CpuBudget budget = options_.budget_seconds > 0
                                 ? CpuBudget::for_this_thread(std::chrono::duration<double>(options_.budget_seconds * scale))
                                 : CpuBudget{};
    double e = energy(u);
    report.energy_start = report.energy = e;
    if (!std::isfinite(e)) {
      report.stop = CanonicalMapStop::LineSearchFailed;  // the start itself has a bad face: nothing to relax from
      report.seconds = CpuBudget::thread_cpu_seconds() - cpu0;
      return report;
    }
    build_pattern(u.rows());
    linalg::SparseCholesky cholesky;
    Eigen::VectorXd g;
    report.stop = CanonicalMapStop::IterationCap;
    double damping = kInitialDamping;
    for (int it = 0; it < options_.max_iterations; ++it) {
      if (budget.expired() || deadline.expired()) {
        report.stop = CanonicalMapStop::TimeBudget;
        break;
      }
      const auto bases = tangent_bases(u);
      assemble(u, bases, g);
      // Global rotations leave E unchanged (a 3-dimensional null space of the Hessian), the projection may add more,
      // and the Hessian omits the sphere's curvature terms: a Levenberg–Marquardt shift keeps the system definite and
      // the step inside the region where the model holds. It shrinks after a full step and grows after a halved one
      // (measured on real spines: a fixed 1e-10 shift stalls at 20 halvings per step, 1e-6 adaptive converges).
      const double mean_diagonal = hessian_.diagonal().mean();
      double shift = damping * mean_diagonal;
      bool factored = false;
      if (options_.scaled_damping) {
        // Marquardt's scaling: the shift of unknown i is damping × H_ii (floored at 1e-12 of the mean, so that a
        // vertex of a flat patch still has a definite row). A shift relative to the MEAN diagonal is dominated by the
        // few area-starved faces of a progressive start (H_ii up to 1e20 × the rest) and freezes every other vertex.
        const Eigen::VectorXd diagonal = hessian_.diagonal();
        const double floor = 1e-12 * mean_diagonal;
        double lambda = damping;
        for (int attempt = 0; attempt < 6 && !factored; ++attempt) {
          for (Eigen::Index i = 0; i < diagonal.size(); ++i)
            hessian_.valuePtr()[diagonal_slots_[static_cast<size_t>(i)]] =
                diagonal(i) + lambda * std::max(diagonal(i), floor);
          factored = cholesky.factorize(hessian_, 0.0);
          if (!factored) lambda *= 100;
        }
        shift = lambda * mean_diagonal;
      } else {
        for (int attempt = 0; attempt < 6 && !factored; ++attempt) {
          factored = cholesky.factorize(hessian_, shift);
          if (!factored) shift *= 100;
        }
      }
      if (!factored) {
        report.stop = CanonicalMapStop::SolverFailed;
        break;
      }
      report.shift = std::max(report.shift, shift);
      const Eigen::VectorXd step = -cholesky.solve(g);
      const double decrement = -g.dot(step);
      report.last_decrement = decrement;
      if (!(decrement >= 0) || !std::isfinite(decrement)) {
        report.stop = CanonicalMapStop::SolverFailed;
        break;
      }
      if (decrement <= options_.absolute_tolerance ||
          decrement <= options_.tolerance * (e - options_.energy.minimum())) {
        report.stop = CanonicalMapStop::Converged;
        break;
      }
      // Backtracking line search from the full step, capped so that no vertex turns by more than 0.25 rad.
      double largest = 0;
      for (Eigen::Index i = 0; i < u.rows(); ++i) largest = std::max(largest, step.segment<2>(2 * i).norm());
      double alpha = std::min(1.0, 0.25 / std::max(largest, 1e-300));
      Eigen::MatrixX3d trial(u.rows(), 3);
      bool accepted = false, alpha_taken_full = false;
      for (int h = 0; h <= options_.max_halvings; ++h, alpha *= 0.5) {
        for (Eigen::Index i = 0; i < u.rows(); ++i)
          trial.row(i) = (u.row(i).transpose() + alpha * bases[static_cast<size_t>(i)] * step.segment<2>(2 * i))
                             .normalized()
                             .transpose();
        const double e_trial = energy(trial);
        if (e_trial <= e - 1e-4 * alpha * decrement) {
          u.swap(trial);
          e = e_trial;
          accepted = true;
          alpha_taken_full = h == 0;
          // Newton underestimates the step on a barrier (on ψ = σ⁻² a full step grows σ by only 4/3): after a full
          // step, keep doubling along the same direction while the energy still falls (and the turn cap holds).
          if (options_.extrapolate && alpha_taken_full) {
            const Eigen::MatrixX3d base = u;
            for (double beta = 2 * alpha; beta * largest <= 0.25; beta *= 2) {
              for (Eigen::Index i = 0; i < u.rows(); ++i)
                trial.row(i) = (base.row(i).transpose() + beta * bases[static_cast<size_t>(i)] * step.segment<2>(2 * i))
                                   .normalized()
                                   .transpose();
              const double e_more = energy(trial);
              if (!(e_more < e)) break;
              u.swap(trial);
              e = e_more;
              ++report.extrapolations;
            }
          }
          break;
        }
        ++report.halvings;
      }
      if (!accepted) {
        if (damping < kMaximalDamping) {  // a stiffer, shorter step may still descend
          damping = std::min(kMaximalDamping, damping * 1e3);
          continue;
        }
        report.stop = CanonicalMapStop::LineSearchFailed;
        break;
      }
      damping = !alpha_taken_full ? std::min(kMaximalDamping, damping * 10) : std::max(kMinimalDamping, damping * 0.3);
      ++report.iterations;
    }
    report.converged = report.stop == CanonicalMapStop::Converged;
    report.energy = e;
    report.seconds = CpuBudget::thread_cpu_seconds() - cpu0;
    return report;
  }

 private:
  // The 2V × 2V pattern (a 2×2 block per vertex pair of a face) and, per face, the positions of its 36 entries in
  // the compressed values, so that each Newton step writes the values in place.
  void build_pattern(Eigen::Index vertex_count) {
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(static_cast<size_t>(faces_.rows()) * 36);
    for (Eigen::Index f = 0; f < faces_.rows(); ++f)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          for (int r = 0; r < 2; ++r)
            for (int c = 0; c < 2; ++c) entries.emplace_back(2 * faces_(f, a) + r, 2 * faces_(f, b) + c, 0.0);
    hessian_.resize(2 * vertex_count, 2 * vertex_count);
    hessian_.setFromTriplets(entries.begin(), entries.end());
    hessian_.makeCompressed();
    slots_.resize(static_cast<size_t>(faces_.rows()) * 36);
    const int* outer = hessian_.outerIndexPtr();
    const int* inner = hessian_.innerIndexPtr();
    for (Eigen::Index f = 0; f < faces_.rows(); ++f)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          for (int r = 0; r < 2; ++r)
            for (int c = 0; c < 2; ++c) {
              const int row = 2 * faces_(f, a) + r, col = 2 * faces_(f, b) + c;
              const int* pos = std::lower_bound(inner + outer[col], inner + outer[col + 1], row);
              slots_[static_cast<size_t>(f) * 36 + static_cast<size_t>(((a * 3 + b) * 2 + r) * 2 + c)] =
                  static_cast<int>(pos - inner);
            }
    diagonal_slots_.resize(static_cast<size_t>(2 * vertex_count));
    for (Eigen::Index i = 0; i < 2 * vertex_count; ++i)
      diagonal_slots_[static_cast<size_t>(i)] =
          static_cast<int>(std::lower_bound(inner + outer[i], inner + outer[i + 1], static_cast<int>(i)) - inner);
  }

  // Gradient g (2V, tangent coordinates) and the projected Hessian (values of hessian_) at u.
  void assemble(const Eigen::MatrixX3d& u, const std::vector<Eigen::Matrix<double, 3, 2>>& bases, Eigen::VectorXd& g) {
    g.setZero(2 * u.rows());
    double* values = hessian_.valuePtr();
    std::fill(values, values + hessian_.nonZeros(), 0.0);
    ChordFrame frame;
    for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
      chord_frame(u, faces_, f, min_height_, frame);  // every accepted map is bijective: the frame exists
      const Eigen::Matrix2d& dm_inv = reference_.inverse_shape[static_cast<size_t>(f)];
      const Eigen::Matrix2d F = frame.shape * dm_inv;
      const double w = reference_.weight(f);
      Eigen::Matrix2d dpsi;
      options_.energy.gradient(F, dpsi);
      const Eigen::Matrix4d hess = options_.energy.projected_hessian(F);
      // B (4×6): vec(F) from the local coordinates (q₀, q₁, q₂); F = [q₁ − q₀, q₂ − q₀] Dm⁻¹.
      // R (6×6): local coordinates from the tangent unknowns, block k = axesᵀ T_{i_k}. J = B R (4×6).
      Eigen::Matrix<double, 4, 6> J = Eigen::Matrix<double, 4, 6>::Zero();
      for (int k = 0; k < 3; ++k) {
        const Eigen::Matrix2d R = frame.axes.transpose() * bases[static_cast<size_t>(faces_(f, k))];
        for (int j = 0; j < 2; ++j) {
          const double coef = k == 0 ? -(dm_inv(0, j) + dm_inv(1, j)) : dm_inv(k - 1, j);
          // F(r, j) += coef · q_k(r): rows 2j + r of J, columns 2k.. of the local unknowns, times R.
          J.block<2, 2>(2 * j, 2 * k) += coef * R;
        }
      }
      const Eigen::Vector4d dpsi_vec(dpsi(0, 0), dpsi(1, 0), dpsi(0, 1), dpsi(1, 1));
      const Eigen::Matrix<double, 6, 1> gf = w * J.transpose() * dpsi_vec;
      const Eigen::Matrix<double, 6, 6> hf = w * J.transpose() * hess * J;
      for (int a = 0; a < 3; ++a) {
        g.segment<2>(2 * faces_(f, a)) += gf.segment<2>(2 * a);
        for (int b = 0; b < 3; ++b)
          for (int r = 0; r < 2; ++r)
            for (int c = 0; c < 2; ++c)
              values[slots_[static_cast<size_t>(f) * 36 + static_cast<size_t>(((a * 3 + b) * 2 + r) * 2 + c)]] +=
                  hf(2 * a + r, 2 * b + c);
      }
    }
  }

  const Eigen::MatrixX3i& faces_;
  const CanonicalMapOptions& options_;
  const double min_height_;
  const ReferenceTriangles reference_;
  Eigen::SparseMatrix<double> hessian_;
  std::vector<int> slots_;
  std::vector<int> diagonal_slots_;  // position of H_ii in the compressed values
};

void check_sizes(const Eigen::MatrixX3d& sphere, const Eigen::MatrixX3d& input_vertices) {
  if (sphere.rows() != input_vertices.rows())
    throw InvalidInputError("invalid_parameter",
                            "the sphere map has " + std::to_string(sphere.rows()) + " points for " +
                                std::to_string(input_vertices.rows()) + " vertices",
                            {{"sphere_points", std::int64_t{sphere.rows()}},
                             {"vertices", std::int64_t{input_vertices.rows()}}});
}

}  // namespace canonical_map_detail

using canonical_map_detail::Relaxation;
using canonical_map_detail::check_sizes;

CanonicalMapReport relax_to_canonical_map(Eigen::MatrixX3d& sphere, const Eigen::MatrixX3d& input_vertices,
                                          const Eigen::MatrixX3i& faces, const CanonicalMapOptions& options,
                                          double min_height, const Deadline& deadline) {
  check_sizes(sphere, input_vertices);
  return Relaxation(input_vertices, faces, options, min_height).run(sphere, deadline);
}

double canonical_map_energy(const Eigen::MatrixX3d& sphere, const Eigen::MatrixX3d& input_vertices,
                            const Eigen::MatrixX3i& faces, const CanonicalMapOptions& options, double min_height) {
  check_sizes(sphere, input_vertices);
  return Relaxation(input_vertices, faces, options, min_height).energy(sphere);
}

}  // namespace wish::spherical
