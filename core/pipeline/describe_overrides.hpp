#pragma once
// The descriptor settings a front end may override, typed: the service parses its `method`, `lmax` and `steps`
// parameters into one, `wish describe` and `wish map` their flags. Absent = the defaults (describe) or the model's
// recipe (classify: server/compute_service.cpp check_descriptor_settings refuses a value that differs from it).
// Eigen-free, so that the service's request types (server/request_parsing.hpp, included beside httplib) can hold
// one: MapMethod is declared opaque here and defined, with its name table, in core/spherical_map/spherical_map.hpp.

#include <optional>
#include <string>

namespace wish {

enum class MapMethod;
struct SphericalMapOptions;
struct PipelineOptions;

struct DescribeOverrides {
  std::optional<MapMethod> method;
  std::optional<int> lmax;
  // The step cap of the chosen method's own flow (core/spherical_map/flow_step_cap.hpp): the service's `steps`,
  // the CLI's --steps. A linear map has no flow: check_overrides refuses a cap for it.
  std::optional<int> max_flow_steps;

  bool any() const { return method || lmax || max_flow_steps; }
  bool operator==(const DescribeOverrides&) const = default;
};

// Throws InvalidInputError("invalid_parameter", details {parameter: steps_name, method}) for a step cap given with
// the linear method (it would be silently ignored). `steps_name` is what the front end calls it ("steps", "--steps").
void check_overrides(const DescribeOverrides& overrides, const std::string& steps_name);

// The overrides over `options`: the method first, then the step cap of that method's flow.
void apply_overrides(const DescribeOverrides& overrides, SphericalMapOptions& options);
void apply_overrides(const DescribeOverrides& overrides, PipelineOptions& options);

}  // namespace wish
