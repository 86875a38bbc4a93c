#include "core/spherical_map/density_equalizing.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>

#include "core/common/cpu_budget.hpp"
#include "core/common/errors.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/spherical_map/map_verification.hpp"

namespace wish {

const char* to_string(AreaCorrection correction) {
  switch (correction) {
    case AreaCorrection::None: return "none";
    case AreaCorrection::DensityEqualizing: return "density_equalizing";
  }
  return "none";
}

AreaCorrection area_correction_from_name(const std::string& name) {
  if (name == "none" || name == "conformal") return AreaCorrection::None;
  if (name == "density_equalizing" || name == "dem") return AreaCorrection::DensityEqualizing;
  throw InvalidInputError("invalid_parameter",
                          "unknown area correction '" + name + "' (expected none | density_equalizing)");
}

const char* to_string(AreaCorrectionStop stop) {
  switch (stop) {
    case AreaCorrectionStop::NotRun: return "not_run";
    case AreaCorrectionStop::Converged: return "converged";
    case AreaCorrectionStop::Plateau: return "plateau";
    case AreaCorrectionStop::IterationCap: return "iteration_cap";
    case AreaCorrectionStop::StepRejected: return "step_rejected";
    case AreaCorrectionStop::TimeBudget: return "time_budget";
    case AreaCorrectionStop::Reverted: return "reverted";
  }
  return "?";
}

namespace spherical {
namespace {

// Input area shares m_f (Σ = 1) and the mask of faces with meaningful input area (the threshold of measure_map).
struct InputShares {
  Eigen::VectorXd share;
  std::vector<char> counted;
};

InputShares input_shares(const Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces) {
  const Eigen::Index nf = faces.rows();
  InputShares s;
  s.share.resize(nf);
  s.counted.assign(static_cast<size_t>(nf), 0);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = x.row(faces(f, 0)), b = x.row(faces(f, 1)), c = x.row(faces(f, 2));
    s.share[f] = 0.5 * (b - a).cross(c - a).norm();
  }
  const double total = s.share.sum();
  const double min_area = 1e-14 * total / static_cast<double>(std::max<Eigen::Index>(1, nf));
  for (Eigen::Index f = 0; f < nf; ++f) s.counted[static_cast<size_t>(f)] = s.share[f] > min_area;
  s.share /= total;
  return s;
}

Eigen::VectorXd chord_areas(const Eigen::MatrixX3d& u, const Eigen::MatrixX3i& faces) {
  Eigen::VectorXd a(faces.rows());
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d p = u.row(faces(f, 0)), q = u.row(faces(f, 1)), r = u.row(faces(f, 2));
    a[f] = 0.5 * (q - p).cross(r - p).norm();
  }
  return a;
}

AreaDistortionFigures figures_of(const InputShares& in, const Eigen::VectorXd& sphere_area) {
  AreaDistortionFigures fig;
  const double total = sphere_area.sum();
  std::vector<double> logs;
  logs.reserve(static_cast<size_t>(sphere_area.size()));
  double abs_sum = 0;
  for (Eigen::Index f = 0; f < sphere_area.size(); ++f) {
    if (!in.counted[static_cast<size_t>(f)]) continue;
    const double l = std::log((sphere_area[f] / total) / in.share[f]);
    const double a = std::isfinite(l) ? std::abs(l) : std::numeric_limits<double>::infinity();
    logs.push_back(a);
    abs_sum += a;
    fig.energy += in.share[f] * a * a;
  }
  if (logs.empty()) return fig;
  fig.area_distortion = std::exp(abs_sum / static_cast<double>(logs.size()));
  fig.log_ratio_max = *std::max_element(logs.begin(), logs.end());
  const size_t idx = std::min(logs.size() - 1, static_cast<size_t>(std::ceil(0.99 * static_cast<double>(logs.size()))) - 1);
  std::nth_element(logs.begin(), logs.begin() + static_cast<std::ptrdiff_t>(idx), logs.end());
  fig.log_ratio_p99 = logs[idx];
  return fig;
}

// Undirected edges of the triangulation and, per face corner k, the edge opposite it (between corners k+1, k+2).
struct EdgeTable {
  std::vector<std::pair<int, int>> ends;
  Eigen::MatrixX3i opposite;  // F×3 edge index
};

EdgeTable edge_table(const Eigen::MatrixX3i& faces, Eigen::Index nv) {
  EdgeTable t;
  t.opposite.resize(faces.rows(), 3);
  std::vector<std::vector<std::pair<int, int>>> by_vertex(static_cast<size_t>(nv));  // (other end, edge)
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      int i = faces(f, (k + 1) % 3), j = faces(f, (k + 2) % 3);
      if (i > j) std::swap(i, j);
      auto& list = by_vertex[static_cast<size_t>(i)];
      auto it = std::find_if(list.begin(), list.end(), [j](const auto& p) { return p.first == j; });
      int e;
      if (it == list.end()) {
        e = static_cast<int>(t.ends.size());
        t.ends.emplace_back(i, j);
        list.emplace_back(j, e);
      } else {
        e = it->second;
      }
      t.opposite(f, k) = e;
    }
  return t;
}

bool any_bad_face(const Eigen::MatrixX3d& u, const Eigen::MatrixX3i& faces, double min_height) {
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    if (is_bad_sphere_face(u, faces, f, min_height)) return true;
  return false;
}

// Area energy E = Σ_f m_f (log r_f)² of the counted faces (+inf when a face has no area).
double area_energy(const InputShares& in, const Eigen::VectorXd& sphere_area) {
  const double total = sphere_area.sum();
  double e = 0;
  for (Eigen::Index f = 0; f < sphere_area.size(); ++f) {
    if (!in.counted[static_cast<size_t>(f)]) continue;
    const double l = std::log((sphere_area[f] / total) / in.share[f]);
    e += in.share[f] * l * l;
  }
  return std::isfinite(e) ? e : std::numeric_limits<double>::infinity();
}

// Per-vertex shares: input mass m_i and sphere area a_i (a third of each incident face's share).
void vertex_shares(const Eigen::MatrixX3i& faces, const InputShares& in, const Eigen::VectorXd& area, Eigen::VectorXd& m,
                   Eigen::VectorXd& a) {
  const double total = area.sum();
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      m[faces(f, k)] += in.share[f] / 3.0;
      a[faces(f, k)] += area[f] / total / 3.0;
    }
}

// The (capped) displacement field of one step at unit step factor (see the header): the potential ψ of the
// excess mass, L ψ = 4π (m − a), the velocity v = −∇ψ / μ with μ_i = m_i / a_i, tangent, times options.step,
// capped at max_step × the shortest incident sphere edge.
Eigen::MatrixX3d displacement(const Eigen::MatrixX3d& u, const Eigen::MatrixX3i& faces, const EdgeTable& edges,
                              const InputShares& in, const Eigen::VectorXd& area,
                              const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& poisson,
                              const AreaCorrectionOptions& o) {
  const Eigen::Index nv = u.rows(), nf = faces.rows();
  Eigen::VectorXd m = Eigen::VectorXd::Zero(nv), a = Eigen::VectorXd::Zero(nv);
  vertex_shares(faces, in, area, m, a);
  const Eigen::VectorXd excess = 4.0 * std::numbers::pi * (m - a);
  Eigen::VectorXd psi = poisson.solve(excess);
  if (!psi.allFinite()) psi.setZero();
  // Face gradients of ψ on the chord triangles (∇B_k = n̂ × e_k / 2A, e_k the edge opposite corner k, CCW),
  // area-averaged to the vertices.
  Eigen::MatrixX3d gradient = Eigen::MatrixX3d::Zero(nv, 3);
  Eigen::VectorXd weight_sum = Eigen::VectorXd::Zero(nv);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d p[3] = {u.row(faces(f, 0)), u.row(faces(f, 1)), u.row(faces(f, 2))};
    const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    const double twice_area = n.norm();
    if (!(twice_area > 0)) continue;
    const Eigen::Vector3d nhat = n / twice_area;
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) g += psi[faces(f, k)] * nhat.cross(p[(k + 2) % 3] - p[(k + 1) % 3]) / twice_area;
    for (int k = 0; k < 3; ++k) {
      gradient.row(faces(f, k)) += 0.5 * twice_area * g.transpose();
      weight_sum[faces(f, k)] += 0.5 * twice_area;
    }
  }
  Eigen::VectorXd shortest = Eigen::VectorXd::Constant(nv, std::numeric_limits<double>::infinity());
  for (const auto& [i, j] : edges.ends) {
    const double l = (u.row(i) - u.row(j)).norm();
    shortest[i] = std::min(shortest[i], l);
    shortest[j] = std::min(shortest[j], l);
  }
  Eigen::MatrixX3d d(nv, 3);
  for (Eigen::Index i = 0; i < nv; ++i) {
    Eigen::Vector3d g = weight_sum[i] > 0 ? Eigen::Vector3d(gradient.row(i).transpose() / weight_sum[i])
                                          : Eigen::Vector3d::Zero();
    const Eigen::Vector3d ui = u.row(i);
    g -= g.dot(ui) * ui;  // tangent part
    const double density = a[i] > 0 ? m[i] / a[i] : std::numeric_limits<double>::infinity();
    Eigen::Vector3d v = density > 0 ? Eigen::Vector3d(-o.step * g / density) : Eigen::Vector3d(-o.step * g);
    const double cap = o.max_step * shortest[i], len = v.norm();
    if (!(len <= cap)) v *= (std::isfinite(len) && len > 0) ? cap / len : 0.0;
    d.row(i) = v.transpose();
  }
  return d;
}

}  // namespace

AreaDistortionFigures area_distortion_figures(const Eigen::MatrixX3d& input_vertices, const Eigen::MatrixX3i& faces,
                                              const Eigen::MatrixX3d& sphere) {
  return figures_of(input_shares(input_vertices, faces), chord_areas(sphere, faces));
}

AreaCorrectionReport equalize_sphere_density(Eigen::MatrixX3d& sphere, const Eigen::MatrixX3d& input_vertices,
                                             const Eigen::MatrixX3i& faces, const AreaCorrectionOptions& options,
                                             double min_height) {
  const double cpu0 = CpuBudget::thread_cpu_seconds();
  AreaCorrectionReport report;
  report.method = AreaCorrection::DensityEqualizing;
  const InputShares in = input_shares(input_vertices, faces);
  Eigen::VectorXd area = chord_areas(sphere, faces);
  report.before = report.after = figures_of(in, area);
  const double budget_seconds =
      options.budget_seconds * std::max(1.0, static_cast<double>(sphere.rows()) / 10000.0);
  const CpuBudget budget = options.budget_seconds > 0
                               ? CpuBudget::for_this_thread(std::chrono::duration<double>(budget_seconds))
                               : CpuBudget{};
  const EdgeTable edges = edge_table(faces, sphere.rows());
  // The Poisson operator: the robust intrinsic Laplacian of the INPUT mesh (cotan weights are conformally
  // invariant, so it is the sphere's Laplacian of the conformal start), regularised by a tiny mass term (L is
  // singular; the excess mass sums to 0), factorised once.
  const geometry::IntrinsicOperator op = geometry::intrinsic_operator(input_vertices, faces);
  const double mean_mass = op.mass.mean();
  Eigen::SparseMatrix<double> system = op.laplacian;
  for (Eigen::Index i = 0; i < system.rows(); ++i) system.coeffRef(i, i) += 1e-8 * op.mass[i] / mean_mass;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> poisson(system);
  if (poisson.info() != Eigen::Success) {
    report.stop = AreaCorrectionStop::StepRejected;
    report.seconds = CpuBudget::thread_cpu_seconds() - cpu0;
    return report;
  }
  double energy = area_energy(in, area);
  double factor = 1.0;
  double best_energy = energy;
  Eigen::MatrixX3d best = sphere;
  Eigen::VectorXd best_area = area;
  int since_best = 0;  // step factor: halved on a rejected step, doubled back (up to 1) after an accepted one
  report.stop = AreaCorrectionStop::IterationCap;
  while (true) {
    if (report.before.log_ratio_p99 < options.tolerance && report.iterations == 0) {
      report.stop = AreaCorrectionStop::Converged;
      break;
    }
    if (report.iterations >= options.max_iterations) {
      report.stop = AreaCorrectionStop::IterationCap;
      break;
    }
    if (budget.expired()) {
      report.stop = AreaCorrectionStop::TimeBudget;
      break;
    }
    const Eigen::MatrixX3d d = displacement(sphere, faces, edges, in, area, poisson, options);
    bool accepted = false;
    int halvings = 0;
    Eigen::MatrixX3d trial;
    Eigen::VectorXd trial_area;
    double trial_energy = energy;
    while (halvings <= options.max_halvings) {
      trial = sphere + factor * d;
      trial.rowwise().normalize();
      if (trial.allFinite() && !any_bad_face(trial, faces, min_height)) {
        trial_area = chord_areas(trial, faces);
        trial_energy = area_energy(in, trial_area);
        // The flow is not the gradient flow of E, so E may rise for a step (DEM moves mass first where the
        // diffused density is steep); a step that raises it by more than max_energy_rise is rejected, and the
        // best map seen is returned.
        if (trial_energy < energy * (1 + options.max_energy_rise)) {
          accepted = true;
          break;
        }
      }
      factor *= 0.5;
      ++halvings;
      ++report.rejected_steps;
    }
    if (!accepted) {
      report.stop = AreaCorrectionStop::StepRejected;
      break;
    }
    sphere = std::move(trial);
    area = std::move(trial_area);
    ++report.iterations;
    energy = trial_energy;
    factor = std::min(1.0, 2.0 * factor);
    if (energy < best_energy * (1 - options.plateau)) {
      best_energy = energy;
      best = sphere;
      best_area = area;
      since_best = 0;
    } else if (++since_best >= options.plateau_steps) {
      report.stop = AreaCorrectionStop::Plateau;
      break;
    }
    const AreaDistortionFigures now = figures_of(in, area);
    if (now.log_ratio_p99 < options.tolerance) {
      report.stop = AreaCorrectionStop::Converged;
      best = sphere;
      best_area = area;
      break;
    }
  }
  if (best_energy < energy) {  // the best map seen, not the last
    sphere = std::move(best);
    area = std::move(best_area);
  }
  report.after = figures_of(in, area);
  report.converged = report.stop == AreaCorrectionStop::Converged || report.stop == AreaCorrectionStop::Plateau;
  report.seconds = CpuBudget::thread_cpu_seconds() - cpu0;
  return report;
}

}  // namespace spherical
}  // namespace wish
