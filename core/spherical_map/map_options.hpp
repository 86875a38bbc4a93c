#pragma once
// The options of the whole sphere-map stage (a recipe's `map` group, descriptor_recipe_codec.hpp): which method
// starts the chain, each method's own options (declared beside the method), the operator, verification, the
// chain's budgets and the area correction.

#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/spherical_map/canonical_map.hpp"
#include "core/spherical_map/cmcf.hpp"
#include "core/spherical_map/density_equalizing.hpp"
#include "core/spherical_map/linear_map.hpp"
#include "core/spherical_map/map_types.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/willmore_flow.hpp"

namespace wish {

struct SphericalMapOptions {
  MapMethod method = MapMethod::Willmore;
  WillmoreOptions willmore;
  CmcfOptions cmcf;
  LinearMapOptions linear;
  LinearSolverKind solver = LinearSolverKind::Cholmod;
  bool fallback = true;              // on failure: more steps, the filtered flow, cMCF, the linear method (§7)
  // Added: before verification, relax the few vertices around flipped / numerically degenerate faces (untangle.hpp).
  bool untangle = true;
  MapVerificationThresholds verification;
  // Added: the operator behind every Laplacian and mass of the flows, the Poisson step, cMCF and the linear map
  // (intrinsic_laplacian.hpp: mollified lengths + intrinsic Delaunay by default).
  geometry::IntrinsicOptions laplacian;
  // Added: time budget of the FLOW attempts, in CPU seconds of the calling thread (cpu_budget.hpp: load on the
  // machine does not change which method a mesh ends on) per 10,000 vertices (at least this many seconds). It is
  // checked before every step try, including the retries of a rejected step (halved τ). When it has passed, the
  // running flow stops (FlowStop::TimeBudget) and its map is verified: a bijective one is the answer (Ok,
  // distortion in the verdict); no further flow starts, an Ok map already held (a provisional, repaired one) ends
  // the chain, and without an Ok map only the linear attempts run (bijectivity before time). Every attempt the
  // budget skips is listed in SphericalMapResult::skipped_for_budget. 0 = no budget. The request deadline
  // (Deadline) is separate, hard and wall-clock.
  // 2 s of the 3 s per 10K vertices of issue 11 (chain_budget_seconds): the other 1 s is for one step try past the
  // budget, the repair and verification of the flow's map and, without an Ok map, the linear attempts. Measured
  // (bench/map_collection_bench, CPU s): the linear attempt 0.21 s on camel (9.8K vertices); the whole chain at most
  // 2.42 s per 10K vertices over the 43 shared genus-0 meshes (diplodocus; the baseline chain reached 3.30 on man).
  double flow_budget_seconds = 2.0;
  // Added: CPU budget of the WHOLE chain per 10,000 vertices (as above): flows, local repair (untangling),
  // verification and fallbacks, so the final answer comes within it (issue 11: ≤ 3 s per 10K vertices on one core).
  // The flows stop at their own budget or at this one less linear_reserve_seconds, whichever comes first. The
  // repair of a flow's map stops when this budget less linear_reserve_seconds is spent (a linear map's repair may
  // use the rest); a map it leaves with flips fails verification, as without the repair (reported per attempt
  // in repair_budget_stopped). Measured before it: 4.86 CPU s on a 10K-vertex UroCell mitochondrion, 2.3 s of it the
  // repair after a budget-stopped flow. Without an Ok map the linear attempts still run once it is spent
  // (bijectivity before time). 0 = no chain budget.
  double chain_budget_seconds = 3.0;
  // Added: CPU seconds per 10,000 vertices kept for the linear fallback while no Ok map is held (two V×V solves and
  // the repair of their map; measured 0.04–0.36 CPU s on 10K-vertex UroCell mitochondria, 0.21 s on camel).
  double linear_reserve_seconds = 0.4;
  // Added (beyond the paper): an area-aware correction of the returned map when it is Ok (density_equalizing.hpp):
  // none (default: the paper's conformal map) or the density-equalising flow. The corrected map is re-verified
  // (bijectivity: flips, degeneracy, degree); `quality` then describes the corrected map, and the conformal
  // distortion bound (strict_conformal_bound) applies to the conformal map before the correction.
  AreaCorrectionOptions area_correction;
  // Added (issue 37, beyond the paper): the map the descriptor is computed on. None: the chain's own map (the
  // paper's conformal map when a flow made it). Isometric: the chain's map, whichever attempt made it, relaxed to the
  // canonical map of canonical_map.hpp (one definition for every mesh; the chain then only has to find a bijective
  // start). Applied to an Ok map after the chain (and instead of the area correction, which it supersedes).
  CanonicalMapOptions canonical;
  // Added: an Ok map made by `method` is kept against any other method's Ok map, whatever their distortion, and
  // the chain then runs only that method's later attempts. Set for a model whose off-recipe policy refuses other
  // methods' maps (pipeline.cpp options_for_recipe): for it a bijective map by its own method is an answer and
  // another method's is a refusal. Off: the least distorted Ok map wins. Not part of the recipe (derived from its
  // policy), so not in the model file.
  bool prefer_method = false;
  // Added: the chain's needle retry and its needle-aware choice between a flow's map and a one-shot map
  // (map_chain.cpp; docs/design/needle-flows.md). Off (the chain as before issue 24 item 3) only for A/B
  // measurements (bench/map_collection_bench --no-needle-aware). Not part of the recipe, so not in the model file.
  bool needle_aware = true;
  bool operator==(const SphericalMapOptions&) const = default;
};

}  // namespace wish
