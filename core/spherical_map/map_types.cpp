#include "core/spherical_map/map_types.hpp"

namespace wish {

const char* to_string(MapMethod method) { return kMapMethodNames.name(method); }
MapMethod map_method_from_name(const std::string& name) { return kMapMethodNames.parse(name, "map method", "method"); }

const char* to_string(LinearSolverKind solver) { return kLinearSolverNames.name(solver); }
LinearSolverKind linear_solver_from_name(const std::string& name) {
  return kLinearSolverNames.parse(name, "linear solver", "solver");
}

const char* to_string(MapCheck check) { return kMapCheckNames.name(check); }
const char* to_string(FlowStop stop) { return kFlowStopNames.name(stop); }
const char* to_string(MapVerdict verdict) { return kMapVerdictNames.name(verdict); }
const char* to_string(MapStatus status) { return kMapStatusNames.name(status); }

}  // namespace wish
