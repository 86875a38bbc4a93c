#pragma once
// One attempt of the map chain (map_chain.hpp): run one method, take its surface to the sphere (radial projection
// about the area-weighted centroid, mirrored first if the flow everted it), Möbius-balance with the input's vertex
// areas, repair a few bad faces locally (chart_untangle.hpp, then untangle.hpp; bounded by the chain's CPU budget)
// — for the needle retry's maps also the kernel placement, star_kernel_repair.hpp — and verify
// (map_verification.hpp). A map that fails verification is never Ok.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/common/cpu_budget.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/spherical_map/flow_result.hpp"
#include "core/spherical_map/map_context.hpp"
#include "core/spherical_map/map_options.hpp"
#include "core/spherical_map/map_types.hpp"
#include "core/spherical_map/map_verification.hpp"

namespace wish {

// One entry of the chain (plan_attempts()).
// cMCF's time step in the chain's needle retry (at total area 4π; CmcfOptions::delta is 1): on decimated needle-heavy
// spines the flow then gets rounder before it stalls, and its radial projection has a few flips (2-25 on the generated
// spines) that the local repair removes, where δ = 1 leaves hundreds (docs/design/needle-flows.md).
inline constexpr double kNeedleCmcfDelta = 0.1;
// A needle retry's map counts as an answer only while its area distortion exp(mean |log area ratio|) stays below
// this: on nmv_spine_3 the small-step cMCF gave a 0-flip map with K p99 2.8 but area distortion 2.6e9 (the neck and
// base squeezed into a vanishing part of the sphere, where the SH fit cannot see them), against 4 for the
// progressive last resort. Beyond it the chain goes on as if the retry had failed; such a map is kept only when
// nothing after it maps. The retry is new (issue 24 item 3), so no map that existed before it depends on this.
inline constexpr double kNeedleMaxAreaDistortion = 1e3;

struct MapAttemptPlan {
  MapMethod method = MapMethod::Willmore;
  bool filtered = false;
  int max_steps = 0;
  int continue_from = -1;  // Willmore: continue the flowed surface of this earlier attempt (if it hit its cap)
  bool clamp = false;      // linear: always use the clamped (all-positive) weights
  // The chain's needle retry (map_chain.cpp; runs only while no Ok map is held): Willmore with the needle
  // operator (WillmoreOptions::needle_operator), cMCF with the small time step kNeedleCmcfDelta.
  bool needle = false;
  bool operator==(const MapAttemptPlan&) const = default;
};

// One try of one method (the first try and each fallback).
struct MapAttempt {
  MapMethod method = MapMethod::Willmore;
  bool filtered = false;
  int max_steps = 0;
  MapStatus status = MapStatus::Ok;
  MapCheck failed_check = MapCheck::None;
  FlowStop stop = FlowStop::None;    // Added: why the flow stopped
  std::string message;
  MapQuality quality;
  geometry::IntrinsicStats operator_stats;  // Added: mollification / flips of the operator this attempt used
  std::vector<FlowStepRecord> steps;
  double seconds = 0;
  double cpu_seconds = 0;            // Added: CPU seconds of the calling thread (what the flow budget counts)
  double repair_cpu_seconds = 0;     // Added: of which the local repair (untangling) of the map
  bool repair_budget_stopped = false;  // Added: the repair stopped because the chain budget was spent
  // Added: the flowed surface came out inside out (negative signed volume; cMCF through a flat state) and was
  // mirrored before the radial projection (map_attempt.cpp).
  bool everted = false;
  bool hit_step_cap = false;         // Added: the flow ran out of steps (so "more steps" may help)
  bool map_verified = false;         // Added: the map passed verification (it may still be NotConverged)
  int continued_from = -1;           // Added: index of the attempt whose flowed surface this one continued
  bool clamped_weights = false;      // Added: a linear attempt that used the clamped (Tutte) weights
  bool needle = false;               // Added: an attempt of the chain's needle retry (MapAttemptPlan::needle)
  // Added: vertices moved by the needle retry's one-ring kernel placement (star_kernel_repair.hpp), part of
  // quality.repaired_vertices; 0 when the earlier repairs sufficed or it did not remove every bad face.
  long kernel_placed_vertices = 0;
};

namespace spherical {

struct AttemptRun {
  MapAttempt attempt;
  Eigen::MatrixX3d sphere;   // the verified (or failed) map, V×3 unit vectors
  Eigen::MatrixX3d flowed;   // where a continued flow starts (the flow's last surface)
};

// control: the request deadline, the flow's CPU budget and the surface to continue (plan.continue_from);
// repair_budget: the CPU budget of the local repair.
AttemptRun run_attempt(const MapContext& context, const MapAttemptPlan& plan, const SphericalMapOptions& options,
                       const FlowControl& control, const CpuBudget& repair_budget);

}  // namespace spherical
}  // namespace wish
