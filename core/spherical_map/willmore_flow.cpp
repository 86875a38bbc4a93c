#include "core/spherical_map/willmore_flow.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <memory>
#include <string>
#include <vector>

#include "core/common/elapsed.hpp"
#include "core/common/stage_profile.hpp"
#include "core/geometry/face_geometry.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/geometry/mean_curvature.hpp"
#include "core/geometry/roundness.hpp"
#include "core/geometry/vertex_normals.hpp"
#include "core/linalg/sparse_cholesky.hpp"
#include "core/spherical_map/dirac_operator.hpp"
#include "core/spherical_map/spin_transform.hpp"

namespace wish::spherical {
namespace {

using Clock = std::chrono::steady_clock;

// Above this many vertices the Dirac and the Poisson factor are never alive at once: each step frees one's values
// before the other is factored (a 160K-vertex map stays under 1 GiB; the Dirac factor alone is ~0.5 GiB there). At
// or below it both are kept from step to step (nucleus-1, 10.8K vertices: 34 MiB + 3 MiB) and each refactorisation
// writes into the storage of the last: freed and reallocated, its pages were faulted in anew every step — 12 % of a
// nucleus-1 map's CPU samples in the kernel's page-fault handler (perf record), and 2–3 ms of zeroing per MiB on a
// virtual machine.
constexpr Eigen::Index kFreeFactorsAboveVertices = 40000;

// The Dirac eigenproblem in either storage (dirac_operator.hpp); the pattern and the symbolic factorisation are
// built once, with the context's METIS ordering of the vertex graph (postordered) expanded to the blocks (cheaper
// than ordering the big graph). With CHOLMOD the matrix is assembled already permuted by that ordering and
// factored in its natural ordering (no permuted copies per factorisation, CholeskyOptions::prepermuted); λ comes
// back in vertex order.
class DiracSystem {
 public:
  DiracSystem(const MapContext& context, bool use_complex) : vp_(context.pattern()), complex_(use_complex) {
    linalg::CholeskyOptions options = context.cholesky_options(linalg::CholmodMode::Supernodal, false);
    const bool prepermute = options.backend == linalg::CholeskyBackend::Cholmod && !context.ordering().empty();
    static const std::vector<int> kIdentity;
    const std::vector<int>& order = prepermute ? context.ordering() : kIdentity;
    options.prepermuted = prepermute;
    if (complex_) {
      cplx_ = build_dirac_pattern<std::complex<double>>(vp_, order);
      cplx_solver_ = std::make_unique<linalg::ComplexSparseCholesky>(options);
    } else {
      real_ = build_dirac_pattern<double>(vp_, order);
      real_solver_ = std::make_unique<linalg::SparseCholesky>(options);
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
      if (r.ok) lambda = quaternions_from_complex(zx_, cplx_.order);
      return r;
    }
    const EigenSolveReport r = smallest_eigenvector(*real_solver_, real_.matrix, mean_diag, options, rx_);
    if (r.ok) lambda = quaternions_from_permuted(rx_, real_.order);
    return r;
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
  Eigen::VectorXd rx_;
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

// The PSD Laplacian of `edges` (L_ij = −w_ij, L_ii = Σ_j w_ij), with w_ij clamped to ≥ 0 in `edges` first: the
// normal equations of min Σ w_ij |x̃_j − x̃_i − ẽ_ij|², a least-squares fit only when no weight is negative. The
// pattern keeps the clamped (zero) entries, so it is that of the mesh's edges.
Eigen::SparseMatrix<double> clamped_edge_laplacian(std::vector<geometry::IntrinsicEdgeWeight>& edges, Eigen::Index n) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(4 * edges.size() + static_cast<std::size_t>(n));
  for (geometry::IntrinsicEdgeWeight& e : edges) {
    e.weight = std::max(0.0, e.weight);
    t.emplace_back(e.i, e.j, -e.weight);
    t.emplace_back(e.j, e.i, -e.weight);
    t.emplace_back(e.i, e.i, e.weight);
    t.emplace_back(e.j, e.j, e.weight);
  }
  for (Eigen::Index i = 0; i < n; ++i) t.emplace_back(static_cast<int>(i), static_cast<int>(i), 0.0);
  Eigen::SparseMatrix<double> l(n, n);
  l.setFromTriplets(t.begin(), t.end());
  return l;
}

// `laplacian`: the flow's operator (flow_operator()); `curvature`: the intrinsic Delaunay one, used for H, the mass
// and the roundness with WillmoreOptions::needle_operator (then the Poisson weights are also clamped to >= 0).
void update_state(const Eigen::MatrixX3i& faces, const geometry::HalfedgeConnectivity& connectivity,
                  const geometry::IntrinsicOptions& laplacian, const geometry::IntrinsicOptions* curvature,
                  SurfaceState& s) {
  const profile::ScopedStage stage("willmore.surface_state (operator, H, energy)");
  geometry::IntrinsicOperator op = geometry::intrinsic_operator(s.x, faces, connectivity, laplacian);
  s.areas = std::move(op.input_face_areas);
  s.edges = std::move(op.edges);
  s.operator_stats = op.stats;
  s.normals = geometry::vertex_normals(s.x, faces);
  if (curvature) {
    s.laplacian = clamped_edge_laplacian(s.edges, s.x.rows());
    const geometry::IntrinsicOperator delaunay = geometry::intrinsic_operator(s.x, faces, connectivity, *curvature);
    s.mass = delaunay.mass;
    s.h = geometry::mean_curvature(s.x, delaunay.laplacian, s.mass, s.normals);
  } else {
    s.laplacian = std::move(op.laplacian);
    s.mass = std::move(op.mass);
    s.h = geometry::mean_curvature(s.x, s.laplacian, s.mass, s.normals);
  }
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

void fail_solver(FlowResult& result, const std::string& message) {
  result.status = MapStatus::SolverFailed;
  result.failed_check = MapCheck::Solver;
  result.stop = FlowStop::SolverFailed;
  result.message = message;
}

void stop_for_budget(FlowResult& result, const std::string& message) {
  result.status = MapStatus::NotConverged;
  result.failed_check = MapCheck::TimeBudget;
  result.stop = FlowStop::TimeBudget;
  result.message = message;
}

// One flow of one mesh: the solvers (symbolic analysis once), the current surface and the trace.
class WillmoreRun {
 public:
  WillmoreRun(const MapContext& context, const WillmoreOptions& options, const FlowControl& control)
      : context_(context), faces_(context.faces()), connectivity_(geometry::halfedge_connectivity(faces_)),
        options_(options), control_(control),
        laplacian_(flow_operator(context.laplacian())), curvature_operator_(delaunay_operator(context.laplacian())),
        dirac_(context, options.complex_dirac),
        poisson_solver_(context.cholesky_options(linalg::CholmodMode::Auto, true)),
        filter_solver_(context.cholesky_options(linalg::CholmodMode::Auto, true)) {
    eigen_options_.max_iterations = options.max_inverse_iterations;
  }

  FlowResult run() {
    state_.x = control_.start ? *control_.start : context_.normalised_input();
    if (control_.start) normalise_area_and_centre(state_.x, faces_);
    update_state(faces_, connectivity_, laplacian_, curvature(), state_);
    result_.operator_stats = state_.operator_stats;
    result_.initial_energy = result_.energy = state_.energy;
    result_.initial_roundness = result_.roundness = state_.roundness;
    result_.vertices = state_.x;
    if (!state_.finite) {
      result_.status = MapStatus::SolverFailed;
      result_.failed_check = MapCheck::NonFinite;
      result_.stop = FlowStop::NonFinite;
      result_.message = "input geometry gives non-finite curvature or zero-area faces";
      return std::move(result_);
    }
    tau_ = options_.tau;
    bool stopped = false;
    for (int step = 1; step <= options_.max_steps && !stopped; ++step) {
      control_.deadline.check("willmore flow step");
      if (state_.roundness < options_.roundness_tolerance) {
        result_.stop = FlowStop::Converged;
        break;
      }
      if (control_.budget.expired()) {  // soft budget of the chain: stop here, the surface so far is verified as it is
        stop_for_budget(result_, "flow time budget spent after " + std::to_string(step - 1) + " steps at roundness " +
                                     std::to_string(state_.roundness));
        stopped = true;
        break;
      }
      stopped = take_step(step);
    }
    if (result_.status == MapStatus::Ok && !stopped && state_.roundness >= options_.roundness_tolerance) {
      result_.hit_step_cap = true;
      result_.status = MapStatus::NotConverged;
      result_.failed_check = MapCheck::Roundness;
      result_.stop = FlowStop::StepCap;
      result_.message = "roundness " + std::to_string(state_.roundness) + " above tolerance " +
                        std::to_string(options_.roundness_tolerance) + " after " + std::to_string(options_.max_steps) +
                        " steps";
    }
    return std::move(result_);
  }

 private:
  // The spin transformation transforms the edges OF THE IMMERSION (CPS11): the Poisson step must integrate the
  // transformed edges of the mesh's own triangles, whose cotans make ω consistent with 𝔼. An intrinsic Delaunay
  // edge is a geodesic across two triangles, not an edge of the immersion, and its transformed chord is not what λ
  // prescribes (measured: camel 4720 flips, bull degree −1 with it). The flow therefore uses the MOLLIFIED
  // operator on the mesh's own triangles (finite on zero-area faces); cMCF and the linear map use intrinsic
  // Delaunay.
  static geometry::IntrinsicOptions flow_operator(geometry::IntrinsicOptions o) {
    if (o.kind == geometry::LaplacianKind::IntrinsicDelaunay) o.kind = geometry::LaplacianKind::Mollified;
    return o;
  }

  static geometry::IntrinsicOptions delaunay_operator(geometry::IntrinsicOptions o) {
    o.kind = geometry::LaplacianKind::IntrinsicDelaunay;
    return o;
  }
  const geometry::IntrinsicOptions* curvature() const {
    return options_.needle_operator ? &curvature_operator_ : nullptr;
  }

  enum class Try { Accepted, Rejected, Failed };

  // Tries step `step` with the current τ until it is accepted or the flow stops; true when the flow stops.
  bool take_step(int step) {
    for (;;) {
      FlowStepRecord rec;
      SurfaceState next;
      std::string reject;
      const Try outcome = try_step(step, rec, next, reject);
      if (outcome == Try::Failed) return true;
      if (outcome == Try::Accepted) return accept(step, std::move(next));
      if (reject_step(step, reject)) return true;
    }
  }

  // The curvature change's source: H, or the low-pass filtered H_σ = (M + σL)⁻¹ M H. False when the filter's
  // factorisation fails.
  bool curvature_source(Eigen::VectorXd& g) {
    g = state_.h;
    if (!options_.filtered) return true;
    const double edge = geometry::mean_edge_length(state_.x, faces_);
    const double sigma = options_.filter_strength * edge * edge;
    Eigen::SparseMatrix<double> mass_matrix(state_.mass.size(), state_.mass.size());
    mass_matrix.setIdentity();
    mass_matrix.diagonal() = state_.mass;
    filter_matrix_ = sigma * state_.laplacian + mass_matrix;  // the intrinsic pattern changes with the flips
    if (!(filter_solver_.analyze(filter_matrix_) && filter_solver_.factorize(filter_matrix_))) return false;
    g = filter_solver_.solve(Eigen::VectorXd(state_.mass.cwiseProduct(state_.h)));
    return true;
  }

  // One try at the current τ: ρ, λ, the Poisson solve and the new surface's state. Rejected with a reason
  // ("non_finite", "energy", "eigen_residual"), or Failed (a solver failure; result_ says which).
  Try try_step(int step, FlowStepRecord& rec, SurfaceState& next, std::string& reject) {
    const Clock::time_point t_step = Clock::now();
    rec.step = step;
    rec.tau = tau_;
    Clock::time_point t0 = Clock::now();
    Eigen::VectorXd g;
    if (!curvature_source(g)) {
      fail_solver(result_, "filter factorisation failed: " + filter_solver_.message());
      rec.accepted = false;
      rec.note = result_.message;
      result_.steps.push_back(rec);
      return Try::Failed;
    }
    const Eigen::VectorXd rho = -tau_ * project_admissible(g, state_.mass, state_.normals);
    const double mean_diag = [&] {
      const profile::ScopedStage stage("willmore.dirac_assemble");
      return dirac_.assemble(state_.x, faces_, state_.areas, rho);
    }();
    rec.geometry_seconds = seconds_since(t0);
    // λ: smallest eigenvector of 𝔼(ρ).
    const EigenSolveReport eig = [&] {
      const profile::ScopedStage stage("willmore.eigen (factor + inverse iteration)");
      return dirac_.solve(mean_diag, eigen_options_, lambda_);
    }();
    if (release_factors_) dirac_.release_factor();  // one numeric factor alive at a time: the Poisson one is next
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
      result_.steps.push_back(rec);
      fail_solver(result_, "step " + std::to_string(step) + ": " + eig.message);
      return Try::Failed;
    }
    // New positions: divergence of the transformed edges, pinned Poisson solve.
    t0 = Clock::now();
    const bool poisson_ok = [&] {
      const profile::ScopedStage stage("willmore.poisson (incl. next surface state)");
      return poisson_step(next);
    }();
    rec.poisson_seconds = seconds_since(t0);
    if (!poisson_ok) {
      rec.accepted = false;
      rec.note = "Poisson factorisation failed: " + poisson_solver_.message();
      rec.seconds = seconds_since(t_step);
      result_.steps.push_back(rec);
      fail_solver(result_, "step " + std::to_string(step) + ": " + rec.note);
      return Try::Failed;
    }
    rec.energy = next.energy;
    rec.roundness = next.roundness;
    if (!next.finite)
      reject = "non_finite";
    else if (next.energy > state_.energy * (1.0 + options_.energy_increase_tolerance))
      reject = "energy";
    else if (eig.residual > options_.max_eigen_residual)
      reject = "eigen_residual";
    rec.seconds = seconds_since(t_step);
    if (!reject.empty()) rec.accepted = false;
    rec.note = reject;
    result_.steps.push_back(rec);
    return reject.empty() ? Try::Accepted : Try::Rejected;
  }

  // x̃ from L x̃ = ω (vertex 0 pinned), normalised, with its state; false when the factorisation fails.
  bool poisson_step(SurfaceState& next) {
    Eigen::MatrixX3d omega = spin_divergence(state_.x, state_.edges, lambda_);
    omega.row(0).setZero();
    Eigen::SparseMatrix<double> pinned;  // scoped to the step: not alive during the next Dirac factorisation
    pin_vertex(state_.laplacian, 0, pinned);
    if (!(poisson_solver_.analyze(pinned) && poisson_solver_.factorize(pinned))) return false;
    next.x = poisson_solver_.solve(omega);
    if (release_factors_) poisson_solver_.release_values();
    normalise_area_and_centre(next.x, faces_);
    update_state(faces_, connectivity_, laplacian_, curvature(), next);
    return true;
  }

  // After a rejected try: τ halved; true when the flow stops (τ below min_tau, or the budget spent).
  bool reject_step(int step, const std::string& reject) {
    tau_ *= 0.5;
    if (std::abs(tau_) < options_.min_tau) {
      result_.message = "step " + std::to_string(step) + " rejected (" + reject + ") down to tau " +
                        std::to_string(tau_ * 2) + " < 2*min_tau";
      if (reject == "energy") {
        // No step of any size lowers the energy: the flow has stalled at its discrete minimum. Like an energy
        // plateau this is a stop, not a failure; the map is judged by verification (docs/design/spherical-map.md §7).
        result_.message = "stalled: " + result_.message;
        result_.stop = FlowStop::EnergyStall;
      } else {
        result_.status = MapStatus::NotConverged;
        result_.failed_check = reject == "non_finite" ? MapCheck::NonFinite : MapCheck::EigenResidual;
        result_.stop = FlowStop::RejectedSteps;
      }
      return true;
    }
    // The budget inside the rejection loop too: up to log2(tau/min_tau) ≈ 4 retries of a full step (a Dirac and a
    // Poisson factorisation each) would otherwise run past it by up to four step costs (issue 11's time bound).
    // The surface is the last accepted one, verified as it is.
    if (control_.budget.expired()) {
      stop_for_budget(result_, "flow time budget spent in step " + std::to_string(step) + " after a rejected try (" +
                                   reject + ", tau " + std::to_string(tau_ * 2) + ") at roundness " +
                                   std::to_string(state_.roundness));
      return true;
    }
    return false;
  }

  // Takes the accepted surface; true when a stopping criterion is met (converged or a plateau).
  bool accept(int step, SurfaceState next) {
    const double previous_energy = state_.energy, previous_roundness = state_.roundness;
    state_ = std::move(next);
    result_.vertices = state_.x;
    result_.energy = state_.energy;
    result_.roundness = state_.roundness;
    if (state_.roundness < options_.roundness_tolerance) {
      result_.stop = FlowStop::Converged;
      return true;
    }
    if ((previous_energy - state_.energy) < options_.energy_tolerance * previous_energy) {
      result_.stop = FlowStop::EnergyPlateau;  // further steps change nothing
      result_.message = "stalled: energy decrease below " + std::to_string(options_.energy_tolerance) +
                         " at roundness " + std::to_string(state_.roundness);
      return true;
    }
    if (previous_roundness - state_.roundness < options_.roundness_stall * previous_roundness &&
        previous_energy - state_.energy < options_.roundness_stall_energy * previous_energy) {
      result_.stop = FlowStop::RoundnessPlateau;
      result_.message = "stalled: roundness " + std::to_string(state_.roundness) + " fell by less than " +
                        std::to_string(options_.roundness_stall) + " of itself in step " + std::to_string(step);
      return true;
    }
    return false;
  }

  const MapContext& context_;
  const Eigen::MatrixX3i& faces_;
  const geometry::HalfedgeConnectivity connectivity_;  // of faces_: built once, every step's operator starts from it
  const WillmoreOptions& options_;
  const FlowControl& control_;
  const geometry::IntrinsicOptions laplacian_, curvature_operator_;
  DiracSystem dirac_;
  linalg::SparseCholesky poisson_solver_, filter_solver_;
  EigenSolveOptions eigen_options_;
  const bool release_factors_ = context_.vertex_count() > kFreeFactorsAboveVertices;
  Eigen::SparseMatrix<double> filter_matrix_;
  Eigen::VectorXd lambda_;
  SurfaceState state_;
  FlowResult result_;
  double tau_ = 0;
};

}  // namespace

FlowResult willmore_flow(const MapContext& context, const WillmoreOptions& options, const FlowControl& control) {
  return WillmoreRun(context, options, control).run();
}

}  // namespace wish::spherical
