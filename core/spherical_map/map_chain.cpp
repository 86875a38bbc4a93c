#include "core/spherical_map/map_chain.hpp"

#include <algorithm>
#include <chrono>

#include "core/common/cpu_budget.hpp"

namespace wish {

std::vector<MapAttemptPlan> plan_attempts(const SphericalMapOptions& options) {
  // Ordered by cost. A plan is skipped at run time when it cannot help: "more steps" only after a flow that ran
  // out of steps (it continues that flow's surface instead of starting over); any flow once the flow budget is
  // spent, and every plan once it is spent while an Ok map is held (listed in skipped_for_budget). The filtered
  // Willmore flow is no fallback any more, to bound the time (it is a second full Dirac flow): ask for it with
  // willmore.filtered.
  const int n = options.willmore.max_steps;
  const MapAttemptPlan willmore{MapMethod::Willmore, options.willmore.filtered, n};
  const MapAttemptPlan cmcf{MapMethod::Cmcf, false, options.cmcf.max_steps};
  const MapAttemptPlan cmcf_long{MapMethod::Cmcf, false,
                                 std::max(options.cmcf.max_steps, options.cmcf.fallback_max_steps)};
  // After a cMCF attempt that hit its cap: the same flow continued from its surface (attempt 0) up to the long cap.
  const MapAttemptPlan cmcf_more{MapMethod::Cmcf, false, cmcf_long.max_steps, 0};
  // The needle retry (docs/design/needle-flows.md): Willmore with the needle operator (H and mass from the intrinsic
  // Delaunay operator, Poisson weights clamped to >= 0), then cMCF with a ten times smaller time step. Each runs
  // only while no Ok map is held but the other retry flow's (Chain::applies), or — held back by an earlier flow's
  // provisional map — after the linear map when that map wins (Chain::run_deferred_needle_retry): on decimated,
  // needle-heavy meshes the flows above stall with hundreds of flips, these get rounder and leave a few that the
  // local repair and the kernel placement remove (map_attempt.cpp); a mesh that ends on an earlier flow keeps its
  // map (both variants change most maps, so they replace no earlier flow's).
  const MapAttemptPlan willmore_needle{MapMethod::Willmore, options.willmore.filtered, n, -1, false, true};
  const MapAttemptPlan cmcf_needle{MapMethod::Cmcf, false, cmcf_long.max_steps, -1, false, true};
  const MapAttemptPlan linear{MapMethod::Linear, false, 1};
  const MapAttemptPlan linear_clamped{MapMethod::Linear, false, 1, -1, true};
  // The last resort of every chain (progressive_embedding.hpp): bijective by construction, with the area of thin
  // parts kept representable. It runs only while no Ok map is held (Chain::applies), so a mesh that an earlier
  // method maps keeps that map, and also once the budgets are spent (a one-shot method, Chain::skipped).
  const MapAttemptPlan progressive{MapMethod::Progressive, false, 1};
  std::vector<MapAttemptPlan> plans;
  if (options.method == MapMethod::Willmore) {
    plans.push_back(willmore);
    if (options.fallback) {
      plans.push_back({MapMethod::Willmore, options.willmore.filtered, 2 * n, 0});  // more steps
      plans.push_back(cmcf_long);
      if (options.needle_aware) {
        plans.push_back(willmore_needle);
        plans.push_back(cmcf_needle);
      }
      plans.push_back(linear);
      plans.push_back(linear_clamped);
      plans.push_back(progressive);
    }
  } else if (options.method == MapMethod::Cmcf) {
    plans.push_back(cmcf);
    if (options.fallback) {
      if (cmcf_more.max_steps > cmcf.max_steps) plans.push_back(cmcf_more);
      plans.push_back(linear);
      plans.push_back(linear_clamped);
      plans.push_back(willmore);
      plans.push_back(progressive);
    }
  } else if (options.method == MapMethod::Progressive) {
    plans.push_back(progressive);
    if (options.fallback) {
      plans.push_back(linear);
      plans.push_back(linear_clamped);
    }
  } else {
    plans.push_back(linear);
    if (options.fallback) {
      plans.push_back(linear_clamped);
      plans.push_back(cmcf_long);
      plans.push_back(willmore);
      plans.push_back(progressive);
    }
  }
  return plans;
}

namespace spherical {
namespace {

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

// Between two Ok maps: true when `a` should replace `b`. The lower K p99 wins (the held map wins ties), except
// between a flow's map and a one-shot method's (linear, progressive): there the flow's map wins also when its K p99
// over the well-shaped faces (every angle >= 5 degrees, MapQuality::conformal_p99_well_shaped) is no higher. On
// decimated, needle-heavy meshes the all-faces p99 lands on the needles, whose K reads large for small position
// errors, and there the one-shot map often wins by the needles alone (measured on the generated needle spines,
// docs/design/needle-flows.md). The rule only adds cases where a flow wins, so a map that ended on a flow by K p99
// still does. Without options.needle_aware: K p99 alone.
bool less_distorted(const MapAttempt& a, const MapAttempt& b, const SphericalMapOptions& options) {
  const MapQuality &p = a.quality, &q = b.quality;
  if (!options.needle_aware || is_one_shot(a.method) == is_one_shot(b.method)) return p.conformal_p99 < q.conformal_p99;
  const MapQuality& flow = is_one_shot(a.method) ? q : p;
  const MapQuality& shot = is_one_shot(a.method) ? p : q;
  const bool flow_as_good = flow.conformal_p99 <= shot.conformal_p99 ||
                            flow.conformal_p99_well_shaped <= shot.conformal_p99_well_shaped;
  return is_one_shot(a.method) ? !flow_as_good : flow_as_good;
}

// The chain's CPU budgets, scaled with the mesh size, in CPU time of this thread, not wall-clock: the method a
// mesh ends on must not depend on the machine's load. The chain budget bounds everything (flows, repair,
// verification); the flows stop at their own budget or at the chain's less the reserve for the linear fallback,
// whichever comes first; after it, the linear attempts run only without an Ok map.
struct ChainBudgets {
  CpuBudget chain, chain_less_reserve, flow;

  ChainBudgets(const SphericalMapOptions& options, Eigen::Index vertex_count) {
    const double scale = std::max(1.0, static_cast<double>(vertex_count) / 10000.0);
    const auto cpu_budget = [](double seconds) {
      return seconds > 0 ? CpuBudget::for_this_thread(std::chrono::duration<double>(seconds)) : CpuBudget{};
    };
    chain = cpu_budget(options.chain_budget_seconds * scale);
    chain_less_reserve = chain.with_reserve(options.linear_reserve_seconds * scale);
    flow = cpu_budget(options.flow_budget_seconds * scale).earliest(chain_less_reserve);
  }
  // The repair's share: what the chain budget leaves, less the linear reserve for a flow's map (the reserve is for
  // the linear fallback and, with an Ok map held, keeps the verification after the repair inside the chain
  // budget); the linear attempts' repair may use the rest.
  const CpuBudget& repair(MapMethod method) const { return is_one_shot(method) ? chain : chain_less_reserve; }
};

class Chain {
 public:
  Chain(const MapContext& context, const SphericalMapOptions& options, const Deadline& deadline)
      : context_(context), options_(options), deadline_(deadline), budgets_(options, context.vertex_count()),
        plans_(plan_attempts(options)), flowed_(plans_.size()) {}

  ChainOutcome run() {
    for (size_t k = 0; k < plans_.size(); ++k) {
      const Eigen::MatrixX3d* start = nullptr;
      if (!applies(k, start)) continue;
      if (try_plan(k, start)) break;
    }
    run_deferred_needle_retry();
    return std::move(outcome_);
  }

 private:
  // Runs plan k (unless the budget skips it); true when the chain ends here.
  bool try_plan(size_t k, const Eigen::MatrixX3d* start) {
    const MapAttemptPlan& plan = plans_[k];
    if (skipped(plan)) return false;
    deadline_.check("spherical map attempt");
    const FlowControl control{deadline_, budgets_.flow, start};
    AttemptRun run = run_attempt(context_, plan, options_, control, budgets_.repair(plan.method));
    flowed_[k] = std::move(run.flowed);
    return record(std::move(run));
  }

  // The needle retry held back by an earlier flow's provisional map (applies) runs once the chain is done, when a
  // one-shot method's map (linear) beat that flow map: the mesh then ends on a one-shot method with or without the
  // needle retry, so no map that ends on a flow without it changes (measured: the generated needle spines whose
  // repaired cMCF map lost to the linear one, docs/design/needle-flows.md). Its maps compete as every other.
  void run_deferred_needle_retry() {
    if (deferred_needle_.empty() || !holding_ok() || !is_one_shot(chosen().method)) return;
    const std::vector<size_t> deferred = std::move(deferred_needle_);
    deferred_needle_.clear();
    for (size_t k : deferred)
      if (try_plan(k, nullptr)) break;
  }

  // An Ok map that ends the search: a needle retry's map with unbounded area distortion does not
  // (kNeedleMaxAreaDistortion).
  static bool answers(const MapAttempt& a) {
    return a.status == MapStatus::Ok && !(a.needle && a.quality.area_distortion > kNeedleMaxAreaDistortion);
  }
  bool holding_ok() const { return !outcome_.attempts.empty() && answers(chosen()); }
  const MapAttempt& chosen() const { return outcome_.attempts[static_cast<size_t>(outcome_.chosen_attempt)]; }

  // Attempts that would repeat or cannot apply (silent: they are not part of this mesh's chain). Sets `start` for
  // a continued flow.
  bool applies(size_t k, const Eigen::MatrixX3d*& start) {
    const MapAttemptPlan& plan = plans_[k];
    if (plan.continue_from >= 0) {
      const MapAttempt& previous = outcome_.attempts[static_cast<size_t>(plan.continue_from)];
      if (!previous.hit_step_cap || previous.status == MapStatus::SolverFailed) return false;
      start = &flowed_[static_cast<size_t>(plan.continue_from)];
    }
    // The clamped linear map after a linear attempt that was already clamped would repeat the same run.
    if (plan.clamp && !options_.linear.always_clamp && !outcome_.attempts.empty() &&
        outcome_.attempts.back().method == MapMethod::Linear && outcome_.attempts.back().clamped_weights)
      return false;
    // The last resort after other methods: only without an Ok map (a provisional one included), so the maps of
    // meshes that an earlier method maps do not change.
    if (plan.method == MapMethod::Progressive && options_.method != MapMethod::Progressive && holding_ok()) return false;
    // The needle retry likewise: only when the attempts before it gave no Ok map, or only the other needle attempt's
    // provisional one (a held needle map is provisional, else the chain would have ended: the two retry flows leave
    // different maps on the same mesh, and the less distorted one is kept). Held back while an earlier flow's
    // provisional map is held: it runs after the linear map if that map is then the chosen one
    // (run_deferred_needle_retry).
    if (plan.needle && holding_ok() && !chosen().needle) {
      deferred_needle_.push_back(k);
      return false;
    }
    // With prefer_method, an Ok map of the requested method is final against every other method's: only the same
    // method's later attempts (a continued flow) can still replace it.
    if (options_.prefer_method && holding_ok() && plan.method != options_.method && chosen().method == options_.method)
      return false;
    return true;
  }

  // The time bound (issue 11): once the flow budget is spent, no further flow starts, and when an Ok map is
  // already held (a provisional one: repaired and distorted) nothing further runs at all — it is the answer.
  // Without an Ok map the one-shot attempts still run (linear: two V×V solves each; progressive; both bijective by construction):
  // bijectivity comes before time. Every attempt skipped here is listed in skipped_for_budget.
  bool skipped(const MapAttemptPlan& plan) {
    if (outcome_.attempts.empty() || !budgets_.flow.expired()) return false;
    if (is_one_shot(plan.method) && !holding_ok()) return false;
    outcome_.skipped_for_budget.push_back(plan);
    return true;
  }

  // Keeps the attempt (and its map when it is the best so far); true when the chain ends here.
  bool record(AttemptRun run) {
    const MapAttempt& attempt = run.attempt;
    const bool first = outcome_.attempts.empty();
    const bool ok = answers(attempt);
    // An Ok map that needed the local repair and is still distorted is provisional: the rest of the chain (within
    // the budget) may find a map that is bijective as computed and less distorted (measured: the staircase sphere
    // of real_mesh_test, Willmore stalled + repaired K p99 8.3, cMCF 1.1). So is the map of a flow that hit its
    // step cap (its continuation comes next). The least distorted Ok map is returned — of the requested method
    // first, with prefer_method.
    const bool repaired_and_distorted =
        attempt.quality.repaired_vertices > 0 && attempt.quality.verdict == MapVerdict::Distorted;
    const bool provisional = ok && (repaired_and_distorted || attempt.hit_step_cap);
    const bool chosen_ok = !first && answers(chosen());
    // Ok maps are ranked by method (with prefer_method: the requested one first), then by K p99.
    const auto rank = [&](const MapAttempt& a) { return options_.prefer_method && a.method != options_.method; };
    const bool better_ok = ok && (!chosen_ok || rank(attempt) < rank(chosen()) ||
                                  (rank(attempt) == rank(chosen()) && less_distorted(attempt, chosen(), options_)));
    if (first || better_ok || (!chosen_ok && less_bad(attempt, chosen()))) {
      outcome_.chosen_attempt = static_cast<int>(outcome_.attempts.size());
      outcome_.sphere = std::move(run.sphere);
    }
    outcome_.attempts.push_back(std::move(run.attempt));
    return ok && !provisional;
  }

  const MapContext& context_;
  const SphericalMapOptions& options_;
  const Deadline& deadline_;
  const ChainBudgets budgets_;
  const std::vector<MapAttemptPlan> plans_;
  std::vector<Eigen::MatrixX3d> flowed_;
  std::vector<size_t> deferred_needle_;  // needle retry plans held back by an earlier flow's provisional map
  ChainOutcome outcome_;
};

}  // namespace

ChainOutcome run_chain(const MapContext& context, const SphericalMapOptions& options, const Deadline& deadline) {
  return Chain(context, options, deadline).run();
}

}  // namespace spherical
}  // namespace wish
