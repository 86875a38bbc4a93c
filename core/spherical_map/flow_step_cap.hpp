#pragma once
// The one meaning of "steps" (the service's `steps` parameter, `wish map|describe --steps`, the `steps` a model's
// recipe reports): the step cap of the chosen method's own flow, i.e. of the chain's first attempt. The fallback
// chain keeps its own caps (map_chain.cpp plan_attempts: Willmore's "more steps" attempt doubles the cap, cMCF
// as a fallback runs up to cmcf.fallback_max_steps), so a cap set here changes only the first flow, and through it
// the Willmore "more steps" attempt.

#include "core/spherical_map/spherical_map.hpp"

namespace wish {

// Whether the method is a flow with a step cap: the linear map is one solve and the progressive embedding has no
// flow (a cap for either would be ignored).
constexpr bool has_flow_step_cap(MapMethod method) { return !is_one_shot(method); }

// The cap of the chosen method's flow. A one-shot method (linear, progressive) has none; it reports the Willmore cap, the cap of the flow
// its fallback chain may run (what the service's `settings.steps` has always shown for it).
inline int flow_step_cap(const SphericalMapOptions& options) {
  return options.method == MapMethod::Cmcf ? options.cmcf.max_steps : options.willmore.max_steps;
}

// Sets the cap of the chosen method's flow (a linear method's: the Willmore cap, as flow_step_cap reports it).
inline void set_flow_step_cap(SphericalMapOptions& options, int steps) {
  if (options.method == MapMethod::Cmcf) options.cmcf.max_steps = steps;
  else options.willmore.max_steps = steps;
}

}  // namespace wish
