#include "core/sh/sh_descriptor.hpp"

#include "core/common/errors.hpp"

namespace wish {

const char* to_string(FitWeighting weighting) {
  switch (weighting) {
    case FitWeighting::Area: return "area";
    case FitWeighting::Uniform: return "uniform";
  }
  return "area";
}

const char* to_string(FitSolver solver) {
  switch (solver) {
    case FitSolver::Direct: return "direct";
    case FitSolver::Banded: return "banded";
  }
  return "direct";
}

const char* to_string(GramMethod method) {
  switch (method) {
    case GramMethod::Quadrature: return "quadrature";
    case GramMethod::Product: return "product";
  }
  return "quadrature";
}

namespace {
[[noreturn]] void bad_name(const char* what, const std::string& name, const char* allowed) {
  throw InvalidInputError("invalid_parameter",
                          std::string("unknown ") + what + " '" + name + "' (expected " + allowed + ")",
                          {{"value", name}});
}
}  // namespace

FitWeighting fit_weighting_from_name(const std::string& name) {
  if (name == "area") return FitWeighting::Area;
  if (name == "uniform") return FitWeighting::Uniform;
  bad_name("fit weighting", name, "area or uniform");
}

FitSolver fit_solver_from_name(const std::string& name) {
  if (name == "direct") return FitSolver::Direct;
  if (name == "banded") return FitSolver::Banded;
  bad_name("fit solver", name, "direct or banded");
}

GramMethod gram_method_from_name(const std::string& name) {
  if (name == "quadrature") return GramMethod::Quadrature;
  if (name == "product") return GramMethod::Product;
  bad_name("Gram method", name, "quadrature or product");
}

}  // namespace wish
