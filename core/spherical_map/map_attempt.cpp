#include "core/spherical_map/map_attempt.hpp"

#include <chrono>
#include <optional>
#include <vector>

#include "core/common/stage_profile.hpp"
#include "core/geometry/face_geometry.hpp"
#include "core/geometry/mass_matrix.hpp"
#include "core/geometry/roundness.hpp"
#include "core/spherical_map/chart_untangle.hpp"
#include "core/spherical_map/cmcf.hpp"
#include "core/spherical_map/linear_map.hpp"
#include "core/spherical_map/mobius.hpp"
#include "core/spherical_map/ordered_one_rings.hpp"
#include "core/spherical_map/progressive_embedding.hpp"
#include "core/spherical_map/star_kernel_repair.hpp"
#include "core/spherical_map/untangle.hpp"
#include "core/spherical_map/willmore_flow.hpp"

namespace wish::spherical {
namespace {

using Clock = std::chrono::steady_clock;

// The method of `plan` with its options (a continued flow runs the steps its plan adds to the first attempt's).
FlowResult run_method(const MapContext& context, const MapAttemptPlan& plan, const SphericalMapOptions& options,
                      const FlowControl& control) {
  switch (plan.method) {
    case MapMethod::Willmore: {
      WillmoreOptions w = options.willmore;
      w.filtered = plan.filtered;
      w.needle_operator = w.needle_operator || plan.needle;
      w.max_steps = control.start ? plan.max_steps - options.willmore.max_steps : plan.max_steps;
      return willmore_flow(context, w, control);
    }
    case MapMethod::Cmcf: {
      CmcfOptions c = options.cmcf;
      c.max_steps = control.start ? plan.max_steps - options.cmcf.max_steps : plan.max_steps;
      if (plan.needle) c.delta = kNeedleCmcfDelta;
      return cmcf_flow(context, c, control);
    }
    case MapMethod::Linear: {
      LinearMapOptions l = options.linear;
      l.always_clamp = l.always_clamp || plan.clamp;
      return linear_map(context, l, control);
    }
    case MapMethod::Progressive:
      return progressive_map(context, ProgressiveOptions{}, control);
  }
  return {};
}

// Radial projection of a flowed surface about its area-weighted centroid; true when it had to be mirrored first.
// An everted flowed surface is mirrored first. cMCF can pass a thin, flattened shape through a flat state and
// re-inflate it inside out (signed volume +1.07 → −4.11 over 15 steps on a UroCell mitochondrion, with the
// Willmore energy peaking at 2e4 in the flat state): the surface ends nearly round, but its radial projection
// reverses orientation, so every face reads as flipped (degree −1) although the map is a bijection. A mirror
// (z → −z) makes the projection orientation-preserving. K is unchanged (a reflection is an isometry), and so are
// the invariants ξ(l), which are O(3)-invariant (docs/design/sh-and-invariants.md). The flow's equations commute with the
// mirror (they act on each coordinate alike), so a continued flow is unaffected.
bool project_radially(Eigen::MatrixX3d& surface, const Eigen::MatrixX3i& faces, Eigen::MatrixX3d& sphere) {
  bool everted = false;
  if (geometry::signed_volume(surface, faces) < 0) {
    surface.col(2) *= -1.0;
    everted = true;
  }
  const Eigen::VectorXd mass = geometry::lumped_mass(surface, faces);
  const Eigen::Vector3d c = geometry::area_weighted_centroid(surface, mass);
  sphere = surface.rowwise() - c.transpose();
  sphere.rowwise().normalize();
  return everted;
}

// Rounds of kernel placement and Möbius rebalancing after the first (balance_and_repair).
constexpr int kKernelRebalanceRounds = 3;

// The one-ring kernel placement of the bad faces' vertices (star_kernel_repair.hpp), applied only when it leaves
// no bad face (else the map stays as it was and fails verification on its flips). Returns the vertices moved.
long place_in_kernels(const MapContext& context, const SphericalMapOptions& options, const CpuBudget& budget,
                      Eigen::MatrixX3d& sphere, MapAttempt& attempt) {
  const std::optional<std::vector<std::vector<int>>> rings = ordered_one_rings(context.faces(), sphere.rows());
  if (!rings) return 0;
  Eigen::MatrixX3d placed = sphere;
  const StarKernelRepairResult kernel = place_in_star_kernels(placed, context.faces(), *rings, options.verification, {}, budget);
  attempt.repair_budget_stopped = kernel.budget_stopped;
  if (kernel.bad_faces_after > 0 || kernel.budget_stopped) return 0;
  sphere.swap(placed);
  attempt.kernel_placed_vertices += kernel.moved_vertices;
  return kernel.moved_vertices;
}

// Möbius balancing and, with options.untangle, the local repair: the foldover-free energy in a chart per cluster
// first (keeps the map as conformal as it can), the uniform Tutte relaxation for what it leaves, and for the needle
// retry's maps the exact kernel placement for what those leave. All stop when the repair budget is spent: what flips
// remain then fail the verification (never accepted).
MobiusResult balance_and_repair(const MapContext& context, const SphericalMapOptions& options,
                                const CpuBudget& repair_budget, bool balance, Eigen::MatrixX3d& sphere,
                                MapAttempt& attempt) {
  MobiusResult mobius;
  long repaired = 0;
  const auto rebalance = [&] {
    if (balance) return mobius_balance(sphere, context.input_mass());
    MobiusResult kept;  // the method's own normalisation: reported, not changed
    kept.converged = true;
    kept.centroid = Eigen::Vector3d(sphere.transpose() * (context.input_mass() / context.input_mass().sum())).norm();
    return kept;
  };
  if (sphere.allFinite()) {
    {
      const profile::ScopedStage stage("map.mobius");
      mobius = rebalance();
    }
    if (options.untangle) {
      const profile::ScopedStage stage("map.repair (untangle)");
      const double repair0 = CpuBudget::thread_cpu_seconds();
      const ChartUntangleResult charts = untangle_in_charts(sphere, context.mesh().vertices, context.faces(),
                                                            options.verification, {}, repair_budget);
      repaired = charts.moved_vertices;
      attempt.repair_budget_stopped = charts.budget_stopped;
      if (!charts.budget_stopped) {
        const UntangleResult tutte = untangle_sphere_map(sphere, context.faces(), options.verification, {}, repair_budget);
        repaired += tutte.moved_vertices;
        attempt.repair_budget_stopped = tutte.budget_stopped;
        // The needle retry's maps: what the two repairs above leave, the exact one-ring kernel placement
        // (star_kernel_repair.hpp; docs/design/needle-flows.md, "Why the local repairs fail next to needles").
        if (attempt.needle && tutte.bad_faces_after > 0 && !tutte.budget_stopped)
          repaired += place_in_kernels(context, options, repair_budget, sphere, attempt);
      }
      if (repaired > 0) mobius = rebalance();  // the repair moved the centroid a bit
      // The flip test is not Möbius-invariant (a face's circumcircle maps to a circle, but its cap may grow past a
      // hemisphere): the rebalancing can turn a large sliver placed near its kernel's edge back (measured: the 1:5
      // long-neck needle spine, 14 placements, 1 flip after the rebalancing). Place and rebalance again while that
      // happens; the last step is a rebalancing, so what it leaves fails verification.
      for (int again = 0; attempt.kernel_placed_vertices > 0 && again < kKernelRebalanceRounds; ++again) {
        if (count_bad_sphere_faces(sphere, context.faces(), options.verification.degenerate_height) == 0) break;
        const long placed = place_in_kernels(context, options, repair_budget, sphere, attempt);
        if (placed == 0) break;
        repaired += placed;
        mobius = rebalance();
      }
      attempt.repair_cpu_seconds = CpuBudget::thread_cpu_seconds() - repair0;
    }
  }
  attempt.quality.repaired_vertices = repaired;
  return mobius;
}

// Status, failed check and message of the attempt from the flow's outcome and the verification.
void judge(const FlowResult& flow, const MobiusResult& mobius, MapCheck failed, MapAttempt& attempt) {
  attempt.map_verified = failed == MapCheck::None && flow.status != MapStatus::SolverFailed;
  if (flow.status == MapStatus::SolverFailed) {
    attempt.quality.verdict = MapVerdict::Failed;
    attempt.status = MapStatus::SolverFailed;
    attempt.failed_check = flow.failed_check;
    attempt.message = flow.message;
  } else if (failed != MapCheck::None) {
    attempt.status = MapStatus::VerificationFailed;
    attempt.failed_check = failed;
    attempt.message = std::string("map failed verification: ") + to_string(failed) + " (flips " +
                      std::to_string(attempt.quality.flipped_faces) + ", degenerate " +
                      std::to_string(attempt.quality.degenerate_faces) + ", degree " +
                      std::to_string(attempt.quality.degree) + ", K p99 " +
                      std::to_string(attempt.quality.conformal_p99) + ", roundness " + std::to_string(flow.roundness) + ")";
    if (attempt.repair_budget_stopped) attempt.message += "; repair stopped: chain CPU budget spent";
    if (!flow.message.empty()) attempt.message += "; flow: " + flow.message;
  } else if (flow.status == MapStatus::NotConverged &&
             (flow.stop == FlowStop::TimeBudget || flow.stop == FlowStop::StepCap)) {
    // The flow budget is the chain's "stop here": a bijective map of the flow so far is the answer (its distortion
    // is in the verdict), as for a stalled flow; running the rest of the chain would only exceed the time bound.
    // So is the step cap, provisionally: the chain goes on (the same flow continued first) and keeps this map when
    // what follows does no better (measured: a UroCell vesicle whose cMCF map at the cap was bijective, K p99 2.1,
    // and whose continued flow ended with 54 flips, had ended on the linear map, K p99 8.1).
    attempt.message = flow.message + "; its map verified";
  } else if (flow.status == MapStatus::NotConverged) {
    attempt.status = MapStatus::NotConverged;
    attempt.failed_check = flow.failed_check;
    attempt.message = flow.message;
  } else if (!mobius.converged) {
    attempt.status = MapStatus::NotConverged;
    attempt.failed_check = MapCheck::Mobius;
    attempt.message = "Möbius balancing stopped at centroid " + std::to_string(mobius.centroid);
  } else {
    attempt.message = flow.message;  // e.g. "stalled: ..." — a stalled flow whose map verifies is Ok
  }
}

}  // namespace

AttemptRun run_attempt(const MapContext& context, const MapAttemptPlan& plan, const SphericalMapOptions& options,
                       const FlowControl& control, const CpuBudget& repair_budget) {
  const Clock::time_point t0 = Clock::now();
  const double cpu0 = CpuBudget::thread_cpu_seconds();
  AttemptRun run;
  MapAttempt& attempt = run.attempt;
  attempt.method = plan.method;
  attempt.filtered = plan.filtered;
  attempt.needle = plan.needle;
  attempt.max_steps = plan.max_steps;
  attempt.continued_from = control.start ? plan.continue_from : -1;
  FlowResult flow = [&] {
    const profile::ScopedStage stage("map.flow (whole method)");
    return run_method(context, plan, options, control);
  }();
  const profile::ScopedStage after_flow("map.after_flow (project, Mobius, repair, verify)");
  attempt.steps = std::move(flow.steps);
  attempt.hit_step_cap = flow.hit_step_cap;
  attempt.stop = flow.stop;
  attempt.operator_stats = flow.operator_stats;
  attempt.clamped_weights = flow.clamped_weights;
  if (flow.on_sphere)
    run.sphere = flow.vertices;  // a one-shot method maps to the sphere directly
  else
    attempt.everted = project_radially(flow.vertices, context.faces(), run.sphere);
  run.flowed = flow.last.size() > 0 ? std::move(flow.last) : std::move(flow.vertices);  // where a continued flow starts
  const MobiusResult mobius =
      balance_and_repair(context, options, repair_budget, !flow.keep_normalisation, run.sphere, attempt);
  const long repaired = attempt.quality.repaired_vertices;
  {
    const profile::ScopedStage stage("map.verify");
    attempt.quality = measure_map(context.mesh().vertices, context.faces(), run.sphere, options.verification);
  }
  attempt.quality.repaired_vertices = repaired;
  attempt.quality.roundness = flow.roundness;
  attempt.quality.mobius_centroid = mobius.centroid;
  attempt.quality.mobius_iterations = mobius.iterations;
  judge(flow, mobius, failed_map_check(attempt.quality, options.verification), attempt);
  attempt.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  attempt.cpu_seconds = CpuBudget::thread_cpu_seconds() - cpu0;
  return run;
}

}  // namespace wish::spherical
