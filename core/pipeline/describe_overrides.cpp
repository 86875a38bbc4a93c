#include "core/pipeline/describe_overrides.hpp"

#include "core/common/errors.hpp"
#include "core/pipeline/pipeline.hpp"
#include "core/spherical_map/flow_step_cap.hpp"

namespace wish {

void check_overrides(const DescribeOverrides& overrides, const std::string& steps_name) {
  if (overrides.method && overrides.max_flow_steps && !has_flow_step_cap(*overrides.method))
    throw InvalidInputError("invalid_parameter",
                            "parameter " + steps_name + " does not apply to method " + to_string(*overrides.method) +
                                " (one shot, no flow steps)",
                            {{"parameter", steps_name}, {"method", std::string(to_string(*overrides.method))}});
}

void apply_overrides(const DescribeOverrides& overrides, SphericalMapOptions& options) {
  check_overrides(overrides, "steps");
  if (overrides.method) options.method = *overrides.method;
  if (overrides.max_flow_steps) set_flow_step_cap(options, *overrides.max_flow_steps);
}

void apply_overrides(const DescribeOverrides& overrides, PipelineOptions& options) {
  apply_overrides(overrides, options.map);
  if (overrides.lmax) options.sh.lmax = *overrides.lmax;
}

}  // namespace wish
