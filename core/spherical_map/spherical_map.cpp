// compute_spherical_map(): flow → radial projection → Möbius balancing → verification, with the fallback chain
// (docs/design/spherical-map.md §7): (i) step rejection with halved τ (inside the flows), (ii) more steps (continuing the
// flowed surface), (iii) the filtered flow, (iv) cMCF run to convergence, (v) the linear method (§8.2), each
// followed by Möbius balancing and verification; every attempt recorded; first Ok attempt or least-bad returned.
#include "core/spherical_map/spherical_map.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

#include "core/common/cpu_budget.hpp"
#include "core/common/enum_names.hpp"
#include "core/common/errors.hpp"
#include "core/geometry/face_geometry.hpp"
#include "core/geometry/mass_matrix.hpp"
#include "core/geometry/roundness.hpp"
#include "core/geometry/vertex_pattern.hpp"
#include "core/spherical_map/chart_untangle.hpp"
#include "core/spherical_map/cmcf.hpp"
#include "core/spherical_map/linear_map.hpp"
#include "core/spherical_map/map_method_names.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/mobius.hpp"
#include "core/spherical_map/untangle.hpp"
#include "core/spherical_map/willmore_flow.hpp"

namespace wish {

const char* to_string(MapMethod method) { return kMapMethodNames.name(method); }

MapMethod map_method_from_name(const std::string& name) {
  return kMapMethodNames.parse(name, "map method", "method");
}

constexpr EnumNames<LinearSolverKind, 2> kLinearSolverNames{{{
    {LinearSolverKind::Cholmod, "cholmod"},
    {LinearSolverKind::EigenSimplicial, "eigen_simplicial"}}}};

const char* to_string(LinearSolverKind solver) { return kLinearSolverNames.name(solver); }

LinearSolverKind linear_solver_from_name(const std::string& name) {
  return kLinearSolverNames.parse(name, "linear solver", "solver");
}

const char* to_string(MapCheck check) {
  switch (check) {
    case MapCheck::None: return "";
    case MapCheck::NonFinite: return "non_finite";
    case MapCheck::FlippedFaces: return "flipped_faces";
    case MapCheck::DegenerateFaces: return "degenerate_faces";
    case MapCheck::Degree: return "degree";
    case MapCheck::ConformalDistortion: return "conformal_distortion";
    case MapCheck::Roundness: return "roundness";
    case MapCheck::Energy: return "energy";
    case MapCheck::EigenResidual: return "eigen_residual";
    case MapCheck::Solver: return "solver";
    case MapCheck::Mobius: return "mobius";
    case MapCheck::TimeBudget: return "time_budget";
  }
  return "?";
}

const char* to_string(FlowStop stop) {
  switch (stop) {
    case FlowStop::None: return "none";
    case FlowStop::Converged: return "converged";
    case FlowStop::EnergyPlateau: return "energy_plateau";
    case FlowStop::RoundnessPlateau: return "roundness_plateau";
    case FlowStop::EnergyStall: return "energy_stall";
    case FlowStop::StepCap: return "step_cap";
    case FlowStop::RejectedSteps: return "rejected_steps";
    case FlowStop::SolverFailed: return "solver_failed";
    case FlowStop::NonFinite: return "non_finite";
    case FlowStop::TimeBudget: return "time_budget";
  }
  return "?";
}

const char* to_string(MapVerdict verdict) {
  switch (verdict) {
    case MapVerdict::Good: return "good";
    case MapVerdict::Distorted: return "distorted";
    case MapVerdict::Failed: return "failed";
  }
  return "?";
}

const char* to_string(MapStatus status) {
  switch (status) {
    case MapStatus::Ok: return "ok";
    case MapStatus::NotConverged: return "not_converged";
    case MapStatus::VerificationFailed: return "verification_failed";
    case MapStatus::SolverFailed: return "solver_failed";
  }
  return "?";
}

namespace {

using Clock = std::chrono::steady_clock;

void check_preconditions(const Mesh& mesh) {
  const Eigen::Index nv = mesh.vertex_count(), nf = mesh.face_count();
  if (nv < 4 || nf < 4)
    throw WishError(ErrorCategory::Unmappable, "too_small", "a closed mesh needs at least 4 vertices and 4 faces (got " +
                                             std::to_string(nv) + " and " + std::to_string(nf) + ")");
  if (!mesh.vertices.allFinite()) throw InvalidInputError("non_finite_vertex", "mesh has NaN/Inf coordinates");
  if (mesh.faces.minCoeff() < 0 || mesh.faces.maxCoeff() >= nv)
    throw InvalidInputError("index_out_of_range", "face index outside [0, #V)");
  const geometry::VertexPattern pattern = geometry::build_vertex_pattern(nv, mesh.faces);
  const long chi = static_cast<long>(nv) - pattern.edge_count + static_cast<long>(nf);
  if (chi != 2 || 3 * nf != 2 * pattern.edge_count)
    throw WishError(ErrorCategory::Unmappable, "genus_nonzero",
                            "mesh is not a closed genus-0 surface (V - E + F = " + std::to_string(chi) +
                                ", 3F = " + std::to_string(3 * nf) + ", 2E = " + std::to_string(2 * pattern.edge_count) +
                                "); run prepare_for_mapping first",
                            {{"euler_characteristic", std::int64_t{chi}}});
  // Zero-area faces are accepted (the operators mollify them, intrinsic_laplacian.hpp); a face that repeats a
  // vertex is a topological defect.
  Eigen::Index repeated = 0;
  for (Eigen::Index f = 0; f < nf; ++f)
    repeated += mesh.faces(f, 0) == mesh.faces(f, 1) || mesh.faces(f, 1) == mesh.faces(f, 2) ||
                mesh.faces(f, 2) == mesh.faces(f, 0);
  if (repeated > 0)
    throw WishError(ErrorCategory::Unmappable, "degenerate_faces", std::to_string(repeated) + " faces repeat a vertex",
                            {{"count", std::int64_t{repeated}}});
  const double volume = geometry::signed_volume(mesh.vertices, mesh.faces);
  if (!(volume > 0))
    throw WishError(ErrorCategory::Unmappable, "inconsistent_orientation",
                            "signed volume " + std::to_string(volume) + " is not positive: faces must be outward (CCW)",
                            {{"signed_volume", volume}});
}

MapAttempt run_attempt(const Mesh& mesh, const MapAttemptPlan& plan, const SphericalMapOptions& options,
                       const Eigen::VectorXd& input_mass, const Deadline& deadline, const CpuBudget& budget,
                       const CpuBudget& repair_budget, const Eigen::MatrixX3d* start, Eigen::MatrixX3d& flowed,
                       Eigen::MatrixX3d& sphere) {
  const Clock::time_point t0 = Clock::now();
  const double cpu0 = CpuBudget::thread_cpu_seconds();
  MapAttempt attempt;
  attempt.method = plan.method;
  attempt.filtered = plan.filtered;
  attempt.max_steps = plan.max_steps;
  attempt.continued_from = start ? plan.continue_from : -1;
  spherical::FlowResult flow;
  if (plan.method == MapMethod::Willmore) {
    WillmoreOptions w = options.willmore;
    w.filtered = plan.filtered;
    w.max_steps = start ? plan.max_steps - options.willmore.max_steps : plan.max_steps;
    flow = spherical::willmore_flow(mesh, w, options.solver, options.laplacian, deadline, start, budget);
  } else if (plan.method == MapMethod::Cmcf) {
    CmcfOptions c = options.cmcf;
    c.max_steps = start ? plan.max_steps - options.cmcf.max_steps : plan.max_steps;
    flow = spherical::cmcf_flow(mesh, c, options.solver, options.laplacian, deadline, budget, start);
  } else {
    LinearMapOptions l = options.linear;
    l.always_clamp = l.always_clamp || plan.clamp;
    flow = spherical::linear_map(mesh, l, options.solver, options.laplacian);
  }
  attempt.steps = std::move(flow.steps);
  attempt.hit_step_cap = flow.hit_step_cap;
  attempt.stop = flow.stop;
  attempt.operator_stats = flow.operator_stats;
  if (flow.on_sphere) {
    sphere = flow.vertices;  // the linear method maps to the sphere directly
  } else {
    // An everted flowed surface is mirrored first. cMCF can pass a thin, flattened shape through a flat state and
    // re-inflate it inside out (signed volume +1.07 → −4.11 over 15 steps on a UroCell mitochondrion, with the
    // Willmore energy peaking at 2e4 in the flat state): the surface ends nearly round, but its radial projection
    // reverses orientation, so every face reads as flipped (degree −1) although the map is a bijection. A mirror
    // (z → −z) makes the projection orientation-preserving. K is unchanged (a reflection is an isometry), and so
    // are the invariants ξ(l), which are O(3)-invariant (docs/design/sh-and-invariants.md). The flow's equations commute with
    // the mirror (they act on each coordinate alike), so a continued flow is unaffected.
    if (geometry::signed_volume(flow.vertices, mesh.faces) < 0) {
      flow.vertices.col(2) *= -1.0;
      attempt.everted = true;
    }
    // Radial projection about the area-weighted centroid, then Möbius balancing with input vertex areas.
    const Eigen::VectorXd mass = geometry::lumped_mass(flow.vertices, mesh.faces);
    const Eigen::Vector3d c = geometry::area_weighted_centroid(flow.vertices, mass);
    sphere = flow.vertices.rowwise() - c.transpose();
    sphere.rowwise().normalize();
  }
  flowed = flow.last.size() > 0 ? std::move(flow.last) : std::move(flow.vertices);  // where a continued flow starts
  spherical::MobiusResult mobius;
  long repaired = 0;
  if (sphere.allFinite()) {
    mobius = spherical::mobius_balance(sphere, input_mass);
    if (options.untangle) {
      // Foldover-free energy in a chart per cluster first (keeps the map as conformal as it can); the uniform
      // Tutte relaxation for what it leaves. Both stop when the chain's CPU budget for the repair is spent: what
      // flips remain then fail the verification below (never accepted).
      const double repair0 = CpuBudget::thread_cpu_seconds();
      const spherical::ChartUntangleResult charts =
          spherical::untangle_in_charts(sphere, mesh.vertices, mesh.faces, options.verification, {}, repair_budget);
      repaired = charts.moved_vertices;
      attempt.repair_budget_stopped = charts.budget_stopped;
      if (!charts.budget_stopped) {
        const spherical::UntangleResult tutte =
            spherical::untangle_sphere_map(sphere, mesh.faces, options.verification, {}, repair_budget);
        repaired += tutte.moved_vertices;
        attempt.repair_budget_stopped = tutte.budget_stopped;
      }
      if (repaired > 0) mobius = spherical::mobius_balance(sphere, input_mass);  // the repair moved the centroid a bit
      attempt.repair_cpu_seconds = CpuBudget::thread_cpu_seconds() - repair0;
    }
  }
  attempt.quality = spherical::measure_map(mesh.vertices, mesh.faces, sphere, options.verification);
  attempt.quality.repaired_vertices = repaired;
  attempt.quality.roundness = flow.roundness;
  attempt.quality.mobius_centroid = mobius.centroid;
  attempt.quality.mobius_iterations = mobius.iterations;
  const MapCheck failed = spherical::failed_map_check(attempt.quality, options.verification);
  attempt.map_verified = failed == MapCheck::None && flow.status != MapStatus::SolverFailed;
  if (flow.status == MapStatus::SolverFailed) attempt.quality.verdict = MapVerdict::Failed;
  if (flow.status == MapStatus::SolverFailed) {
    attempt.status = MapStatus::SolverFailed;
    attempt.failed_check = flow.failed_check;
    attempt.message = flow.message;
  } else if (failed != MapCheck::None) {
    attempt.status = MapStatus::VerificationFailed;
    attempt.failed_check = failed;
    attempt.message = std::string("map failed verification: ") + to_string(failed) + " (flips " + std::to_string(attempt.quality.flipped_faces) +
                      ", degenerate " + std::to_string(attempt.quality.degenerate_faces) + ", degree " +
                      std::to_string(attempt.quality.degree) + ", K p99 " + std::to_string(attempt.quality.conformal_p99) +
                      ", roundness " + std::to_string(flow.roundness) + ")";
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
  attempt.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  attempt.cpu_seconds = CpuBudget::thread_cpu_seconds() - cpu0;
  return attempt;
}

// Strictly better map for the "least bad" choice when no attempt is Ok (earlier attempts win ties).
bool less_bad(const MapAttempt& a, const MapAttempt& b) {
  if (a.map_verified != b.map_verified) return a.map_verified;
  if (a.map_verified) return a.quality.conformal_p99 < b.quality.conformal_p99;
  const MapQuality &p = a.quality, &q = b.quality;
  if (p.non_finite_vertices != q.non_finite_vertices) return p.non_finite_vertices < q.non_finite_vertices;
  if (p.flipped_faces != q.flipped_faces) return p.flipped_faces < q.flipped_faces;
  if ((p.degree == 1) != (q.degree == 1)) return p.degree == 1;
  if (p.degenerate_faces != q.degenerate_faces) return p.degenerate_faces < q.degenerate_faces;
  return p.conformal_p99 < q.conformal_p99;
}

// The area-aware correction of an Ok map (density_equalizing.hpp), re-verified: a corrected map that is not
// bijective (it should not happen: every step is checked) is dropped and the conformal map kept (stop Reverted).
void correct_area(const Mesh& mesh, const SphericalMapOptions& options, const Eigen::VectorXd& input_mass,
                  SphericalMapResult& result) {
  Eigen::MatrixX3d corrected = result.sphere;
  AreaCorrectionReport report = spherical::equalize_sphere_density(
      corrected, mesh.vertices, mesh.faces, options.area_correction, options.verification.degenerate_height);
  report.conformal_p99_before = result.quality.conformal_p99;
  MapQuality quality = spherical::measure_map(mesh.vertices, mesh.faces, corrected, options.verification);
  MapVerificationThresholds bijective_only = options.verification;
  bijective_only.strict_conformal_bound = false;  // the correction trades conformality for area by design
  if (spherical::failed_map_check(quality, bijective_only) != MapCheck::None) {
    report.stop = AreaCorrectionStop::Reverted;
    report.converged = false;
    report.after = report.before;
    report.conformal_p99_after = report.conformal_p99_before;
    result.area_correction = report;
    return;
  }
  report.conformal_p99_after = quality.conformal_p99;
  quality.repaired_vertices = result.quality.repaired_vertices;
  quality.roundness = result.quality.roundness;
  quality.mobius_iterations = result.quality.mobius_iterations;
  const Eigen::VectorXd w = input_mass / input_mass.sum();
  quality.mobius_centroid = Eigen::Vector3d(corrected.transpose() * w).norm();  // balance after the correction
  result.sphere = std::move(corrected);
  result.quality = quality;
  result.verdict = quality.verdict;
  result.area_correction = report;
}

}  // namespace

std::vector<MapAttemptPlan> plan_attempts(const SphericalMapOptions& options) {
  // Ordered by cost. A plan is skipped at run time when it cannot help: "more steps" only after a flow that ran
  // out of steps (it continues that flow's surface instead of starting over); any flow once the flow budget is
  // spent, and every plan once it is spent while an Ok map is held (listed in skipped_for_budget). The filtered Willmore flow is no fallback any more, to bound the time (it is a second full Dirac flow):
  // ask for it with willmore.filtered.
  const int n = options.willmore.max_steps;
  const MapAttemptPlan willmore{MapMethod::Willmore, options.willmore.filtered, n};
  const MapAttemptPlan cmcf{MapMethod::Cmcf, false, options.cmcf.max_steps};
  const MapAttemptPlan cmcf_long{MapMethod::Cmcf, false,
                                 std::max(options.cmcf.max_steps, options.cmcf.fallback_max_steps)};
  // After a cMCF attempt that hit its cap: the same flow continued from its surface (attempt 0) up to the long cap.
  const MapAttemptPlan cmcf_more{MapMethod::Cmcf, false, cmcf_long.max_steps, 0};
  const MapAttemptPlan linear{MapMethod::Linear, false, 1};
  const MapAttemptPlan linear_clamped{MapMethod::Linear, false, 1, -1, true};
  std::vector<MapAttemptPlan> plans;
  if (options.method == MapMethod::Willmore) {
    plans.push_back(willmore);
    if (options.fallback) {
      plans.push_back({MapMethod::Willmore, options.willmore.filtered, 2 * n, 0});  // more steps
      plans.push_back(cmcf_long);
      plans.push_back(linear);
      plans.push_back(linear_clamped);
    }
  } else if (options.method == MapMethod::Cmcf) {
    plans.push_back(cmcf);
    if (options.fallback) {
      if (cmcf_more.max_steps > cmcf.max_steps) plans.push_back(cmcf_more);
      plans.push_back(linear);
      plans.push_back(linear_clamped);
      plans.push_back(willmore);
    }
  } else {
    plans.push_back(linear);
    if (options.fallback) {
      plans.push_back(linear_clamped);
      plans.push_back(cmcf_long);
      plans.push_back(willmore);
    }
  }
  return plans;
}

SphericalMapResult compute_spherical_map(const Mesh& mesh, const SphericalMapOptions& options, const Deadline& deadline) {
  const Clock::time_point t0 = Clock::now();
  const double cpu0 = CpuBudget::thread_cpu_seconds();
  check_preconditions(mesh);
  const Eigen::VectorXd input_mass = geometry::lumped_mass(mesh.vertices, mesh.faces);

  const std::vector<MapAttemptPlan> plans = plan_attempts(options);
  // Budgets scaled with the mesh size, in CPU time of this thread, not wall-clock: the method a mesh ends on must
  // not depend on the machine's load. The chain budget bounds everything (flows, repair, verification); the flows
  // stop at their own budget or at the chain's less the reserve for the linear fallback, whichever comes first;
  // after it, the linear attempts run only without an Ok map.
  const double scale = std::max(1.0, static_cast<double>(mesh.vertex_count()) / 10000.0);
  const auto cpu_budget = [](double seconds) {
    return seconds > 0 ? CpuBudget::for_this_thread(std::chrono::duration<double>(seconds)) : CpuBudget{};
  };
  const CpuBudget chain = cpu_budget(options.chain_budget_seconds * scale);
  const CpuBudget chain_less_reserve = chain.with_reserve(options.linear_reserve_seconds * scale);
  const CpuBudget budget = cpu_budget(options.flow_budget_seconds * scale).earliest(chain_less_reserve);

  SphericalMapResult result;
  std::vector<Eigen::MatrixX3d> flowed(plans.size());
  Eigen::MatrixX3d best_sphere;
  for (size_t k = 0; k < plans.size(); ++k) {
    const MapAttemptPlan& plan = plans[k];
    // Attempts that would repeat or cannot apply (silent: they are not part of this mesh's chain).
    const Eigen::MatrixX3d* start = nullptr;
    if (plan.continue_from >= 0) {
      const MapAttempt& previous = result.attempts[static_cast<size_t>(plan.continue_from)];
      if (!previous.hit_step_cap || previous.status == MapStatus::SolverFailed) continue;
      start = &flowed[static_cast<size_t>(plan.continue_from)];
    }
    // The clamped linear map after a linear attempt that was already clamped would repeat the same run.
    if (plan.clamp && !options.linear.always_clamp && !result.attempts.empty() &&
        result.attempts.back().method == MapMethod::Linear &&
        result.attempts.back().message.find("clamped") != std::string::npos)
      continue;
    // The time bound (issue 11): once the flow budget is spent, no further flow starts, and when an Ok map is
    // already held (a provisional one: repaired and distorted) nothing further runs at all — it is the answer.
    // Without an Ok map the linear attempts still run (two V×V solves each, bijective by construction):
    // bijectivity comes before time. Every attempt skipped here is listed in skipped_for_budget.
    const bool holding_ok =
        !result.attempts.empty() && result.attempts[static_cast<size_t>(result.chosen_attempt)].status == MapStatus::Ok;
    // With prefer_method, an Ok map of the requested method is final against every other method's: only the same
    // method's later attempts (a continued flow) can still replace it.
    if (options.prefer_method && holding_ok && plan.method != options.method &&
        result.attempts[static_cast<size_t>(result.chosen_attempt)].method == options.method)
      continue;
    if (!result.attempts.empty() && budget.expired()) {
      if (plan.method != MapMethod::Linear || holding_ok) {
        result.skipped_for_budget.push_back(plan);
        continue;
      }
    }
    deadline.check("spherical map attempt");
    // The repair's share: what the chain budget leaves, less the linear reserve for a flow's map (the reserve is
    // for the linear fallback and, with an Ok map held, keeps the verification after the repair inside the chain
    // budget); the linear attempts' repair may use the rest.
    const CpuBudget& repair_budget = plan.method != MapMethod::Linear ? chain_less_reserve : chain;
    Eigen::MatrixX3d sphere;
    MapAttempt attempt =
        run_attempt(mesh, plan, options, input_mass, deadline, budget, repair_budget, start, flowed[k], sphere);
    const bool first = result.attempts.empty();
    const bool ok = attempt.status == MapStatus::Ok;
    // An Ok map that needed the local repair and is still distorted is provisional: the rest of the chain (within
    // the budget) may find a map that is bijective as computed and less distorted (measured: the staircase sphere
    // of real_mesh_test, Willmore stalled + repaired K p99 8.3, cMCF 1.1). So is the map of a flow that hit its
    // step cap (its continuation comes next). The least distorted Ok map is returned — of the requested method
    // first, with prefer_method.
    const bool repaired_and_distorted =
        attempt.quality.repaired_vertices > 0 && attempt.quality.verdict == MapVerdict::Distorted;
    const bool provisional = ok && (repaired_and_distorted || attempt.hit_step_cap);
    const MapAttempt* chosen = first ? nullptr : &result.attempts[static_cast<size_t>(result.chosen_attempt)];
    const bool chosen_ok = chosen && chosen->status == MapStatus::Ok;
    // Ok maps are ranked by method (with prefer_method: the requested one first), then by K p99.
    const auto rank = [&](const MapAttempt& a) { return options.prefer_method && a.method != options.method; };
    const bool better_ok =
        ok && (!chosen_ok || rank(attempt) < rank(*chosen) ||
               (rank(attempt) == rank(*chosen) && attempt.quality.conformal_p99 < chosen->quality.conformal_p99));
    if (first || better_ok || (!chosen_ok && less_bad(attempt, *chosen))) {
      result.chosen_attempt = static_cast<int>(result.attempts.size());
      best_sphere = std::move(sphere);
    }
    result.attempts.push_back(std::move(attempt));
    if (ok && !provisional) break;
  }
  const MapAttempt& chosen = result.attempts[static_cast<size_t>(result.chosen_attempt)];
  result.sphere = std::move(best_sphere);
  result.status = chosen.status;
  result.failed_check = chosen.failed_check;
  result.quality = chosen.quality;
  result.verdict = chosen.quality.verdict;
  result.operator_stats = chosen.operator_stats;
  result.method_used = chosen.method;
  if (options.area_correction.method != AreaCorrection::None && result.ok()) correct_area(mesh, options, input_mass, result);
  result.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  result.cpu_seconds = CpuBudget::thread_cpu_seconds() - cpu0;
  return result;
}

}  // namespace wish
