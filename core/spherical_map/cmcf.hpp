#pragma once
// Conformalized mean curvature flow (Kazhdan, Solomon, Ben-Chen 2012; docs/design/spherical-map.md §8.1).
// Semi-implicit MCF with the stiffness frozen at the input:  (M_t + δ L₀) x_{t+1} = M_t x_t,
// L₀ = PSD cot Laplacian of the (area-4π normalised) input, M_t = lumped mass of the current surface; after each
// step centre on the area-weighted centroid and rescale to area 4π. δ is in units of area at total area 4π
// (δ ≈ 1 ⇔ δ ≈ A/4π for the raw mesh). Stops when roundness < roundness_tolerance (Ok), when the best R has not
// fallen by roundness_stall of itself for stall_patience steps (stalled, Ok with "stalled" in the message: judged by
// verification), or at max_steps (NotConverged, failed_check "roundness", hit_step_cap). Where it stops short of
// convergence it returns its ROUNDEST surface: on elongated shapes R is not monotone (measured on UroCell
// mitochondria: 0.43 → 0.14, a plateau of ~10 steps, then 0.02; or 0.02 → 0.40 when thin parts pinch).
// One V×V factorisation per step; symbolic analysis once.

#include "core/spherical_map/flow_result.hpp"
#include "core/spherical_map/map_context.hpp"

namespace wish {

struct CmcfOptions {
  double delta = 1.0;                // time step at total area 4*pi
  int max_steps = 30;
  double roundness_tolerance = 5e-3;
  // Added: stop (stalled; accepted if the map verifies) when, after min_steps_before_stall steps, R decreases by
  // less than this fraction per step.
  double roundness_stall = 1e-3;
  int min_steps_before_stall = 10;
  // Added: ... for this many steps in a row (1: the first step that does not lower R stops the flow). The flow
  // returns its roundest surface. Chosen on the 91 UroCell mitochondria (bench/map_collection_bench --method cmcf,
  // the chain of a cMCF model): patience 1 stalled cMCF at R ≈ 0.14 on the way down, and 76 ended on a cMCF map;
  // 10: 80; 15: 86; 20: 87, but the longer flows left the fallbacks too little of the CPU budget (2 maps failed,
  // against 1 at 1, 10 and 15).
  int stall_patience = 15;
  // Added: step cap when cMCF runs as a fallback of the Willmore flow: cheap per step (one V×V factorisation), so
  // it is run (nearly) to convergence as Kazhdan et al. do.
  int fallback_max_steps = 200;
  bool operator==(const CmcfOptions&) const = default;
};

namespace spherical {

// L₀ and the first M_t: the context's normalised_operator(). control.start (optional): flowed positions to continue
// from (input connectivity), e.g. the surface of an earlier attempt that hit its step cap; L₀ stays the input's,
// so a continued flow is the same flow run longer. control.budget: soft CPU-time limit (FlowStop::TimeBudget).
FlowResult cmcf_flow(const MapContext& context, const CmcfOptions& options, const FlowControl& control = {});

}  // namespace spherical
}  // namespace wish
