#pragma once
// The name tables of the SH fit's enums (sh_descriptor.hpp): to_string / *_from_name, the CLI's --weights and
// --solver choices and the OpenAPI FitWeighting, FitSolver and GramMethod schemas (wire/contract_enums.cpp).

#include "core/common/enum_names.hpp"
#include "core/sh/sh_descriptor.hpp"

namespace wish {

inline constexpr EnumNames<FitWeighting, 2> kFitWeightingNames{{{
    {FitWeighting::Area, "area"},
    {FitWeighting::Uniform, "uniform"}}}};

inline constexpr EnumNames<FitSolver, 2> kFitSolverNames{{{
    {FitSolver::Direct, "direct"},
    {FitSolver::Banded, "banded"}}}};

inline constexpr EnumNames<GramMethod, 2> kGramMethodNames{{{
    {GramMethod::Quadrature, "quadrature"},
    {GramMethod::Product, "product"}}}};

inline constexpr EnumNames<FitSampling, 2> kFitSamplingNames{{{
    {FitSampling::Vertices, "vertices"},
    {FitSampling::Surface, "surface"}}}};

}  // namespace wish
