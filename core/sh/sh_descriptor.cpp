#include "core/sh/sh_descriptor.hpp"

#include "core/common/enum_names.hpp"
#include "core/common/errors.hpp"

namespace wish {

constexpr EnumNames<FitWeighting, 2> kFitWeightingNames{{{
    {FitWeighting::Area, "area"},
    {FitWeighting::Uniform, "uniform"}}}};

const char* to_string(FitWeighting weighting) { return kFitWeightingNames.name(weighting); }

constexpr EnumNames<FitSolver, 2> kFitSolverNames{{{
    {FitSolver::Direct, "direct"},
    {FitSolver::Banded, "banded"}}}};

const char* to_string(FitSolver solver) { return kFitSolverNames.name(solver); }

constexpr EnumNames<GramMethod, 2> kGramMethodNames{{{
    {GramMethod::Quadrature, "quadrature"},
    {GramMethod::Product, "product"}}}};

const char* to_string(GramMethod method) { return kGramMethodNames.name(method); }

FitWeighting fit_weighting_from_name(const std::string& name) {
  return kFitWeightingNames.parse(name, "fit weighting", "value");
}

FitSolver fit_solver_from_name(const std::string& name) {
  return kFitSolverNames.parse(name, "fit solver", "value");
}

GramMethod gram_method_from_name(const std::string& name) {
  return kGramMethodNames.parse(name, "Gram method", "value");
}

}  // namespace wish
