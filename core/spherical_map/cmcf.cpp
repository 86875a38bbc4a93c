#include "core/spherical_map/cmcf.hpp"

#include <chrono>
#include <cmath>

#include "core/common/elapsed.hpp"
#include "core/geometry/cotan_laplacian.hpp"
#include "core/geometry/face_geometry.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/geometry/mass_matrix.hpp"
#include "core/geometry/mean_curvature.hpp"
#include "core/geometry/roundness.hpp"
#include "core/geometry/vertex_normals.hpp"
#include "core/linalg/sparse_cholesky.hpp"

namespace wish::spherical {
namespace {
using Clock = std::chrono::steady_clock;

// Willmore energy for the step trace, from the mollified operator (finite on zero-area faces).
double robust_willmore_energy(const Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces,
                              const geometry::HalfedgeConnectivity& connectivity,
                              const geometry::IntrinsicOptions& laplacian) {
  geometry::IntrinsicOptions o = laplacian;
  if (o.kind == geometry::LaplacianKind::IntrinsicDelaunay) o.kind = geometry::LaplacianKind::Mollified;
  const geometry::IntrinsicOperator op = geometry::intrinsic_operator(x, faces, connectivity, o);
  return geometry::willmore_energy(geometry::mean_curvature(x, op.laplacian, op.mass, geometry::vertex_normals(x, faces)),
                                   op.mass);
}
}  // namespace

FlowResult cmcf_flow(const MapContext& context, const CmcfOptions& options, const FlowControl& control) {
  FlowResult result;
  const Eigen::MatrixX3i& faces = context.faces();
  const geometry::IntrinsicOptions& laplacian = context.laplacian();
  const geometry::HalfedgeConnectivity connectivity = geometry::halfedge_connectivity(faces);  // once per flow
  linalg::SparseCholesky solver(context.cholesky_options(linalg::CholmodMode::Auto, false));

  // L₀: the intrinsic operator of the input normalised to area 4π (mollified, intrinsic Delaunay: nonnegative
  // weights, so the implicit step is an M-matrix solve). M_t: lumped mass from mollified face areas of the current
  // surface (positions are extrinsic by nature: the flow moves them).
  Eigen::MatrixX3d x = context.normalised_input();
  const geometry::IntrinsicOperator& op = context.normalised_operator();
  result.operator_stats = op.stats;
  const Eigen::SparseMatrix<double>& l0 = op.laplacian;
  Eigen::SparseMatrix<double> mass_matrix(x.rows(), x.rows());
  mass_matrix.setIdentity();
  Eigen::VectorXd mass = op.mass;
  if (control.start) {  // continue an earlier run: its surface and that surface's mass, the input's L₀
    x = *control.start;
    mass = geometry::lumped_mass(faces, geometry::mollified_face_areas(x, faces, laplacian.mollify_delta), x.rows());
  }
  result.initial_energy = result.energy = robust_willmore_energy(x, faces, connectivity, laplacian);
  result.initial_roundness = result.roundness = geometry::roundness(x, mass);
  result.vertices = x;
  Eigen::SparseMatrix<double> system;
  bool converged = result.roundness < options.roundness_tolerance;
  // The roundest surface so far and the step it came from: on elongated shapes R is not monotone (it can fall to
  // 0.02 and climb back to 0.4 when thin parts pinch), so the flow hands back its roundest surface, not its last.
  Eigen::MatrixX3d roundest = x;
  double roundest_r = result.roundness, roundest_energy = result.energy;
  int roundest_step = 0;
  const auto keep_roundest = [&] {
    if (roundest_r < result.roundness) {
      result.last = std::move(result.vertices);
      result.vertices = roundest;
      result.roundness = roundest_r;
      result.energy = roundest_energy;
    }
  };
  for (int step = 1; step <= options.max_steps && !converged; ++step) {
    control.deadline.check("cmcf step");
    if (control.budget.expired()) {  // soft budget of the chain: keep the (roundest) surface so far, verified as it is
      keep_roundest();
      result.status = MapStatus::NotConverged;
      result.failed_check = MapCheck::TimeBudget;
      result.stop = FlowStop::TimeBudget;
      result.message = "cMCF time budget spent after " + std::to_string(step - 1) + " steps at roundness " +
                       std::to_string(result.roundness);
      return result;
    }
    const Clock::time_point t_step = Clock::now();
    FlowStepRecord rec;
    rec.step = step;
    rec.tau = options.delta;
    mass_matrix.diagonal() = mass;
    system = options.delta * l0 + mass_matrix;  // same pattern every step: symbolic analysis once
    Clock::time_point t0 = Clock::now();
    if (!solver.factorize(system)) {
      rec.accepted = false;
      rec.note = solver.message();
      result.steps.push_back(rec);
      result.status = MapStatus::SolverFailed;
      result.failed_check = MapCheck::Solver;
      result.stop = FlowStop::SolverFailed;
      result.message = "cMCF step " + std::to_string(step) + ": " + solver.message();
      return result;
    }
    rec.factor_seconds = seconds_since(t0);
    t0 = Clock::now();
    Eigen::MatrixX3d next = solver.solve(Eigen::MatrixXd(mass.asDiagonal() * x));
    normalise_area_and_centre(next, faces);
    rec.poisson_seconds = seconds_since(t0);
    t0 = Clock::now();
    const Eigen::VectorXd areas = geometry::mollified_face_areas(next, faces, laplacian.mollify_delta);
    if (!next.allFinite() || !areas.allFinite()) {
      rec.accepted = false;
      rec.note = "non_finite";
      result.steps.push_back(rec);
      result.status = MapStatus::SolverFailed;
      result.failed_check = MapCheck::NonFinite;
      result.stop = FlowStop::NonFinite;
      result.message = "cMCF step " + std::to_string(step) + " produced non-finite positions";
      return result;
    }
    x = std::move(next);
    mass = geometry::lumped_mass(faces, areas, x.rows());
    rec.roundness = geometry::roundness(x, mass);
    rec.energy = robust_willmore_energy(x, faces, connectivity, laplacian);
    rec.geometry_seconds = seconds_since(t0);
    rec.seconds = seconds_since(t_step);
    result.steps.push_back(rec);
    result.vertices = x;
    result.roundness = rec.roundness;
    result.energy = rec.energy;
    converged = rec.roundness < options.roundness_tolerance;
    if (rec.roundness < (1.0 - options.roundness_stall) * roundest_r) roundest_step = step;
    if (rec.roundness < roundest_r) {
      roundest = x;
      roundest_r = rec.roundness;
      roundest_energy = rec.energy;
    }
    if (!converged && step >= options.min_steps_before_stall && step - roundest_step >= options.stall_patience) {
      // Stalled: R has not fallen by roundness_stall for stall_patience steps (Kazhdan et al. run to this point);
      // judged by verification like a plateau.
      keep_roundest();
      result.message = "stalled: roundness " + std::to_string(roundest_r) + " (step " + std::to_string(roundest_step) +
                       ") not bettered in " + std::to_string(step - roundest_step) + " steps";
      result.stop = FlowStop::RoundnessPlateau;
      return result;
    }
  }
  if (converged) result.stop = FlowStop::Converged;
  if (!converged) {
    keep_roundest();
    result.hit_step_cap = true;
    result.status = MapStatus::NotConverged;
    result.failed_check = MapCheck::Roundness;
    result.stop = FlowStop::StepCap;
    result.message = "cMCF roundness " + std::to_string(result.roundness) + " above tolerance " +
                     std::to_string(options.roundness_tolerance) + " after " + std::to_string(options.max_steps) +
                     " steps";
  }
  return result;
}

}  // namespace wish::spherical
