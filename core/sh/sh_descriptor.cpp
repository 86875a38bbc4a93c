#include "core/sh/sh_descriptor.hpp"

#include "core/common/enum_names.hpp"
#include "core/common/errors.hpp"
#include "core/sh/sh_fit_names.hpp"

namespace wish {

const char* to_string(FitWeighting weighting) { return kFitWeightingNames.name(weighting); }

const char* to_string(FitSolver solver) { return kFitSolverNames.name(solver); }

const char* to_string(GramMethod method) { return kGramMethodNames.name(method); }

const char* to_string(FitSampling sampling) { return kFitSamplingNames.name(sampling); }

FitWeighting fit_weighting_from_name(const std::string& name) {
  return kFitWeightingNames.parse(name, "fit weighting", "value");
}

FitSolver fit_solver_from_name(const std::string& name) {
  return kFitSolverNames.parse(name, "fit solver", "value");
}

GramMethod gram_method_from_name(const std::string& name) {
  return kGramMethodNames.parse(name, "Gram method", "value");
}

FitSampling fit_sampling_from_name(const std::string& name) {
  return kFitSamplingNames.parse(name, "fit sampling", "value");
}

}  // namespace wish
