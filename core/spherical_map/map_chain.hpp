#pragma once
// The fallback chain (docs/design/spherical-map.md §7): the planned attempts in order of cost, each run by run_attempt()
// (map_attempt.hpp), stopping at the first Ok attempt that is final (a repaired, still distorted Ok map, or the
// map of a flow that hit its step cap, is provisional: the chain goes on within its budget). Every attempt is
// recorded; the chosen one is the least distorted Ok attempt or, when none is Ok, the least-bad one.
// Budgets (issue 11), in CPU seconds of the calling thread per 10,000 vertices: the flows stop at their own budget
// or at the chain's less the linear reserve; once the flow budget is spent no further flow starts, and without an
// Ok map the linear attempts still run (bijectivity before time).

#include <vector>

#include <Eigen/Core>

#include "core/common/deadline.hpp"
#include "core/spherical_map/map_attempt.hpp"
#include "core/spherical_map/map_context.hpp"
#include "core/spherical_map/map_options.hpp"

namespace wish {

// The chain for `options`, ordered by cost (docs/design/spherical-map.md §7): the requested method, then (with fallback)
// more steps of the same flow, cMCF run to its stall, the linear map with intrinsic weights, the clamped
// (Tutte) linear map. Attempts that cannot help are skipped at run time (see run_chain).
std::vector<MapAttemptPlan> plan_attempts(const SphericalMapOptions& options);

namespace spherical {

struct ChainOutcome {
  Eigen::MatrixX3d sphere;                       // the map of attempts[chosen_attempt]
  std::vector<MapAttempt> attempts;              // in order
  int chosen_attempt = 0;
  std::vector<MapAttemptPlan> skipped_for_budget;  // planned attempts the budget skipped, in plan order
};

ChainOutcome run_chain(const MapContext& context, const SphericalMapOptions& options, const Deadline& deadline);

}  // namespace spherical
}  // namespace wish
