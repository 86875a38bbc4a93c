#include "core/spherical_map/willmore_flow.hpp"

#include <chrono>
#include <complex>
#include <memory>
#include <vector>
#include <cmath>
#include <numbers>
#include <string>

#include "core/geometry/cotan_laplacian.hpp"
#include "core/geometry/face_geometry.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/geometry/mass_matrix.hpp"
#include "core/geometry/mean_curvature.hpp"
#include "core/geometry/roundness.hpp"
#include "core/geometry/vertex_normals.hpp"
#include "core/geometry/vertex_pattern.hpp"
#include "core/linalg/sparse_cholesky.hpp"
#include "core/spherical_map/dirac_operator.hpp"
#include "core/spherical_map/spin_transform.hpp"

namespace wish::spherical {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

linalg::CholeskyOptions cholesky_options(LinearSolverKind kind, linalg::CholmodMode mode, std::vector<int> perm) {
  linalg::CholeskyOptions o;
  o.backend = kind == LinearSolverKind::Cholmod ? linalg::CholeskyBackend::Cholmod
                                                : linalg::CholeskyBackend::EigenSimplicial;
  o.cholmod_mode = mode;
  if (kind == LinearSolverKind::Cholmod) o.permutation = std::move(perm);
  return o;
}

// The Dirac eigenproblem in either storage (dirac_operator.hpp); the pattern and the symbolic factorisation are
// built once, with a METIS ordering of the vertex graph expanded to the blocks (cheaper than ordering the big graph).
class DiracSystem {
 public:
  DiracSystem(const geometry::VertexPattern& vp, bool use_complex, LinearSolverKind kind, const std::vector<int>& perm)
      : vp_(vp), complex_(use_complex) {
    if (complex_) {
      cplx_ = build_dirac_pattern<std::complex<double>>(vp);
      cplx_solver_ = std::make_unique<linalg::ComplexSparseCholesky>(
          cholesky_options(kind, linalg::CholmodMode::Supernodal, perm.empty() ? perm : linalg::expand_ordering(perm, 2)));
    } else {
      real_ = build_dirac_pattern<double>(vp);
      real_solver_ = std::make_unique<linalg::SparseCholesky>(
          cholesky_options(kind, linalg::CholmodMode::Supernodal, perm.empty() ? perm : linalg::expand_ordering(perm, 4)));
    }
  }
  double assemble(const Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces, const Eigen::VectorXd& areas,
                  const Eigen::VectorXd& rho) {
    return complex_ ? assemble_dirac(vp_, cplx_, x, faces, areas, rho) : assemble_dirac(vp_, real_, x, faces, areas, rho);
  }
  // λ as a 4V quaternion field.
  EigenSolveReport solve(double mean_diag, const EigenSolveOptions& options, Eigen::VectorXd& lambda) {
    if (complex_) {
      const EigenSolveReport r = smallest_eigenvector(*cplx_solver_, cplx_.matrix, mean_diag, options, zx_);
      if (r.ok) lambda = quaternions_from_complex(zx_);
      return r;
    }
    return smallest_eigenvector(*real_solver_, real_.matrix, mean_diag, options, lambda);
  }
  // Frees the numeric factor once λ is known (the symbolic analysis stays for the next step).
  void release_factor() {
    if (complex_) cplx_solver_->release_values();
    else real_solver_->release_values();
  }

 private:
  const geometry::VertexPattern& vp_;
  bool complex_;
  DiracPattern real_;
  ComplexDiracPattern cplx_;
  std::unique_ptr<linalg::SparseCholesky> real_solver_;
  std::unique_ptr<linalg::ComplexSparseCholesky> cplx_solver_;
  Eigen::VectorXcd zx_;
};

// Everything derived from the current positions. The Laplacian, the mass and the areas come from the intrinsic
// operator of the current surface (mollified lengths, intrinsic Delaunay flips; intrinsic_laplacian.hpp), so
// zero-area and needle faces give finite, nonnegative weights. The Dirac matrix is necessarily EXTRINSIC — a spin
// transformation acts on the immersion, so it needs the edge vectors of the mesh's own faces — but takes the
// mollified face areas (1/A_f stays finite on a zero-area face). The normals are the angle-weighted extrinsic
// ones (zero-area faces contribute nothing).
struct SurfaceState {
  Eigen::MatrixX3d x;
  Eigen::VectorXd areas, mass, h;
  Eigen::MatrixX3d normals;
  std::vector<geometry::IntrinsicEdgeWeight> edges;
  Eigen::SparseMatrix<double> laplacian;
  geometry::IntrinsicStats operator_stats;
  double energy = 0, roundness = 0;
  bool finite = true;
};

void update_state(const Eigen::MatrixX3i& faces, const geometry::IntrinsicOptions& laplacian, SurfaceState& s) {
  geometry::IntrinsicOperator op = geometry::intrinsic_operator(s.x, faces, laplacian);
  s.areas = std::move(op.input_face_areas);
  s.laplacian = std::move(op.laplacian);
  s.mass = std::move(op.mass);
  s.edges = std::move(op.edges);
  s.operator_stats = op.stats;
  s.normals = geometry::vertex_normals(s.x, faces);
  s.h = geometry::mean_curvature(s.x, s.laplacian, s.mass, s.normals);
  s.energy = geometry::willmore_energy(s.h, s.mass);
  s.roundness = geometry::roundness(s.x, s.mass);
  s.finite = s.x.allFinite() && s.laplacian.coeffs().allFinite() && s.h.allFinite() && std::isfinite(s.energy) &&
             s.areas.minCoeff() > 0 && s.mass.minCoeff() > 0;
}

// P(g) = g − Σ_k ⟨g, u_k⟩_M u_k with {u_k} the M-orthonormalised {1, N_x, N_y, N_z} (modified Gram–Schmidt, two
// passes). Removes the constant (first-order integrability) and Möbius (normal-translation) components.
Eigen::VectorXd project_admissible(const Eigen::VectorXd& g, const Eigen::VectorXd& mass, const Eigen::MatrixX3d& normals) {
  const Eigen::Index n = g.size();
  Eigen::Matrix<double, Eigen::Dynamic, 4> basis(n, 4);
  basis.col(0).setOnes();
  basis.rightCols(3) = normals;
  auto dot = [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a.array() * mass.array() * b.array()).sum(); };
  for (int k = 0; k < 4; ++k) {
    Eigen::VectorXd u = basis.col(k);
    for (int pass = 0; pass < 2; ++pass)
      for (int j = 0; j < k; ++j) u -= dot(u, basis.col(j)) * basis.col(j);
    const double norm = std::sqrt(dot(u, u));
    basis.col(k) = norm > 0 ? Eigen::VectorXd(u / norm) : Eigen::VectorXd::Zero(n);
  }
  Eigen::VectorXd out = g;
  for (int k = 0; k < 4; ++k) out -= dot(out, basis.col(k)) * basis.col(k);
  return out;
}

}  // namespace

void normalise_area_and_centre(Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces) {
  const Eigen::VectorXd mass = geometry::lumped_mass(x, faces);
  const double area = mass.sum();
  const Eigen::Vector3d c = geometry::area_weighted_centroid(x, mass);
  x.rowwise() -= c.transpose();
  x *= std::sqrt(4.0 * std::numbers::pi / area);
}

FlowResult willmore_flow(const Mesh& mesh, const WillmoreOptions& options, LinearSolverKind solver_kind,
                         const geometry::IntrinsicOptions& laplacian_options, const Deadline& deadline,
                         const Eigen::MatrixX3d* start, const CpuBudget& budget) {
  FlowResult result;
  // The spin transformation transforms the edges OF THE IMMERSION (CPS11): the Poisson step must integrate the
  // transformed edges of the mesh's own triangles, whose cotans make ω consistent with 𝔼. An intrinsic Delaunay
  // edge is a geodesic across two triangles, not an edge of the immersion, and its transformed chord is not what λ
  // prescribes (measured: camel 4720 flips, bull degree −1 with it). The flow therefore uses the MOLLIFIED
  // operator on the mesh's own triangles (finite on zero-area faces); cMCF and the linear map use intrinsic
  // Delaunay.
  geometry::IntrinsicOptions flow_operator = laplacian_options;
  if (flow_operator.kind == geometry::LaplacianKind::IntrinsicDelaunay)
    flow_operator.kind = geometry::LaplacianKind::Mollified;
  const geometry::IntrinsicOptions& laplacian = flow_operator;
  const Eigen::MatrixX3i& faces = mesh.faces;
  const geometry::VertexPattern pattern = geometry::build_vertex_pattern(mesh.vertex_count(), faces);
  const std::vector<int> perm =
      solver_kind == LinearSolverKind::Cholmod ? linalg::metis_ordering(pattern.pattern) : std::vector<int>{};
  DiracSystem dirac(pattern, options.complex_dirac, solver_kind, perm);
  linalg::SparseCholesky poisson_solver(cholesky_options(solver_kind, linalg::CholmodMode::Auto, perm));
  linalg::SparseCholesky filter_solver(cholesky_options(solver_kind, linalg::CholmodMode::Auto, perm));
  EigenSolveOptions eigen_options;
  eigen_options.max_iterations = options.max_inverse_iterations;

  SurfaceState state;
  state.x = start ? *start : mesh.vertices;
  normalise_area_and_centre(state.x, faces);
  update_state(faces, laplacian, state);
  result.operator_stats = state.operator_stats;
  result.initial_energy = result.energy = state.energy;
  result.initial_roundness = result.roundness = state.roundness;
  result.vertices = state.x;
  if (!state.finite) {
    result.status = MapStatus::SolverFailed;
    result.failed_check = MapCheck::NonFinite;
    result.stop = FlowStop::NonFinite;
    result.message = "input geometry gives non-finite curvature or zero-area faces";
    return result;
  }

  Eigen::SparseMatrix<double> filter_matrix;
  Eigen::VectorXd lambda;
  double tau = options.tau;
  bool stopped = false;
  for (int step = 1; step <= options.max_steps && !stopped; ++step) {
    deadline.check("willmore flow step");
    if (state.roundness < options.roundness_tolerance) {
      result.stop = FlowStop::Converged;
      break;
    }
    if (budget.expired()) {  // soft budget of the chain: stop here, the surface so far is verified as it is
      result.status = MapStatus::NotConverged;
      result.failed_check = MapCheck::TimeBudget;
      result.stop = FlowStop::TimeBudget;
      result.message = "flow time budget spent after " + std::to_string(step - 1) + " steps at roundness " +
                       std::to_string(state.roundness);
      stopped = true;
      break;
    }
    bool accepted = false;
    while (!accepted) {
      const Clock::time_point t_step = Clock::now();
      FlowStepRecord rec;
      rec.step = step;
      rec.tau = tau;
      // Curvature change ρ = −τ P(H) (or of the low-pass filtered H).
      Clock::time_point t0 = Clock::now();
      Eigen::VectorXd g = state.h;
      bool filter_failed = false;
      if (options.filtered) {
        const double edge = geometry::mean_edge_length(state.x, faces);
        const double sigma = options.filter_strength * edge * edge;
        Eigen::SparseMatrix<double> mass_matrix(state.mass.size(), state.mass.size());
        mass_matrix.setIdentity();
        mass_matrix.diagonal() = state.mass;
        filter_matrix = sigma * state.laplacian + mass_matrix;  // the intrinsic pattern changes with the flips
        if (filter_solver.analyze(filter_matrix) && filter_solver.factorize(filter_matrix)) {
          g = filter_solver.solve(Eigen::VectorXd(state.mass.cwiseProduct(state.h)));
        } else {
          filter_failed = true;
        }
      }
      if (filter_failed) {
        result.status = MapStatus::SolverFailed;
        result.failed_check = MapCheck::Solver;
        result.stop = FlowStop::SolverFailed;
        result.message = "filter factorisation failed: " + filter_solver.message();
        rec.accepted = false;
        rec.note = result.message;
        result.steps.push_back(rec);
        stopped = true;
        break;
      }
      const Eigen::VectorXd rho = -tau * project_admissible(g, state.mass, state.normals);
      const double mean_diag = dirac.assemble(state.x, faces, state.areas, rho);
      rec.geometry_seconds = seconds_since(t0);
      // λ: smallest eigenvector of 𝔼(ρ).
      const EigenSolveReport eig = dirac.solve(mean_diag, eigen_options, lambda);
      dirac.release_factor();  // one numeric factor alive at a time: the Poisson one is next
      rec.factor_seconds = eig.factor_seconds;
      rec.eigen_seconds = eig.solve_seconds;
      rec.eigen_residual = eig.residual;
      rec.rayleigh = eig.rayleigh;
      rec.inverse_iterations = eig.iterations;
      rec.eigen_shift = eig.shift;
      if (!eig.ok) {
        rec.accepted = false;
        rec.note = eig.message;
        rec.seconds = seconds_since(t_step);
        result.steps.push_back(rec);
        result.status = MapStatus::SolverFailed;
        result.failed_check = MapCheck::Solver;
        result.stop = FlowStop::SolverFailed;
        result.message = "step " + std::to_string(step) + ": " + eig.message;
        stopped = true;
        break;
      }
      // New positions: divergence of the transformed edges, pinned Poisson solve.
      t0 = Clock::now();
      Eigen::MatrixX3d omega = spin_divergence(state.x, state.edges, lambda);
      omega.row(0).setZero();
      Eigen::SparseMatrix<double> pinned;  // scoped to the step: not alive during the next Dirac factorisation
      pin_vertex(state.laplacian, 0, pinned);
      SurfaceState next;
      bool poisson_ok = poisson_solver.analyze(pinned) && poisson_solver.factorize(pinned);
      if (poisson_ok) {
        next.x = poisson_solver.solve(omega);
        poisson_solver.release_values();
        normalise_area_and_centre(next.x, faces);
        update_state(faces, laplacian, next);
      }
      rec.poisson_seconds = seconds_since(t0);
      if (!poisson_ok) {
        rec.accepted = false;
        rec.note = "Poisson factorisation failed: " + poisson_solver.message();
        rec.seconds = seconds_since(t_step);
        result.steps.push_back(rec);
        result.status = MapStatus::SolverFailed;
        result.failed_check = MapCheck::Solver;
        result.stop = FlowStop::SolverFailed;
        result.message = "step " + std::to_string(step) + ": " + rec.note;
        stopped = true;
        break;
      }
      rec.energy = next.energy;
      rec.roundness = next.roundness;
      std::string reject;
      if (!next.finite)
        reject = "non_finite";
      else if (next.energy > state.energy * (1.0 + options.energy_increase_tolerance))
        reject = "energy";
      else if (eig.residual > options.max_eigen_residual)
        reject = "eigen_residual";
      rec.seconds = seconds_since(t_step);
      if (!reject.empty()) {
        rec.accepted = false;
        rec.note = reject;
        result.steps.push_back(rec);
        tau *= 0.5;
        if (std::abs(tau) < options.min_tau) {
          result.message = "step " + std::to_string(step) + " rejected (" + reject + ") down to tau " +
                           std::to_string(tau * 2) + " < 2*min_tau";
          if (reject == "energy") {
            // No step of any size lowers the energy: the flow has stalled at its discrete minimum. Like an energy
            // plateau this is a stop, not a failure; the map is judged by verification (docs/design/spherical-map.md §7).
            result.message = "stalled: " + result.message;
            result.stop = FlowStop::EnergyStall;
          } else {
            result.status = MapStatus::NotConverged;
            result.failed_check = reject == "non_finite" ? MapCheck::NonFinite : MapCheck::EigenResidual;
            result.stop = FlowStop::RejectedSteps;
          }
          stopped = true;
          break;
        }
        // The budget inside the rejection loop too: up to log2(tau/min_tau) ≈ 4 retries of a full step (a Dirac and
        // a Poisson factorisation each) would otherwise run past it by up to four step costs (issue 11's time
        // bound). The surface is the last accepted one, verified as it is.
        if (budget.expired()) {
          result.status = MapStatus::NotConverged;
          result.failed_check = MapCheck::TimeBudget;
          result.stop = FlowStop::TimeBudget;
          result.message = "flow time budget spent in step " + std::to_string(step) + " after a rejected try (" +
                           reject + ", tau " + std::to_string(tau * 2) + ") at roundness " +
                           std::to_string(state.roundness);
          stopped = true;
          break;
        }
        continue;
      }
      accepted = true;
      result.steps.push_back(rec);
      const double previous_energy = state.energy, previous_roundness = state.roundness;
      state = std::move(next);
      result.vertices = state.x;
      result.energy = state.energy;
      result.roundness = state.roundness;
      if (state.roundness < options.roundness_tolerance) {
        stopped = true;
        result.stop = FlowStop::Converged;
      } else if ((previous_energy - state.energy) < options.energy_tolerance * previous_energy) {
        stopped = true;  // energy plateau: further steps change nothing
        result.stop = FlowStop::EnergyPlateau;
        result.message = "stalled: energy decrease below " + std::to_string(options.energy_tolerance) +
                         " at roundness " + std::to_string(state.roundness);
      } else if (previous_roundness - state.roundness < options.roundness_stall * previous_roundness &&
                 previous_energy - state.energy < options.roundness_stall_energy * previous_energy) {
        stopped = true;  // roundness plateau
        result.stop = FlowStop::RoundnessPlateau;
        result.message = "stalled: roundness " + std::to_string(state.roundness) + " fell by less than " +
                         std::to_string(options.roundness_stall) + " of itself in step " + std::to_string(step);
      }
    }
  }
  if (result.status == MapStatus::Ok && !stopped && state.roundness >= options.roundness_tolerance) {
    result.hit_step_cap = true;
    result.status = MapStatus::NotConverged;
    result.failed_check = MapCheck::Roundness;
    result.stop = FlowStop::StepCap;
    result.message = "roundness " + std::to_string(state.roundness) + " above tolerance " +
                     std::to_string(options.roundness_tolerance) + " after " + std::to_string(options.max_steps) +
                     " steps";
  }
  return result;
}

}  // namespace wish::spherical
