#pragma once
// The name tables of the descriptor recipe's enums (descriptor_recipe.hpp): to_string / *_from_name, the choices of
// `wish train --features / --scale / --off-recipe` and the OpenAPI OffRecipePolicy schema (wire/contract_enums.cpp).

#include "core/classify/descriptor_recipe.hpp"
#include "core/common/enum_names.hpp"

namespace wish {

inline constexpr EnumNames<FeatureFamily, 8> kFeatureFamilyNames{{{
    {FeatureFamily::Invariants, "invariants"},
    {FeatureFamily::Global, "global"},
    {FeatureFamily::Combined, "combined"},
    {FeatureFamily::Spectrum, "spectrum"},
    {FeatureFamily::SpectrumGlobal, "spectrum_global"},
    {FeatureFamily::CanonicalSh, "canonical_sh"},
    {FeatureFamily::CanonicalShGlobal, "canonical_sh_global"},
    {FeatureFamily::All, "all"}}}};

inline constexpr EnumNames<ScaleNormalization, 3> kScaleNormalizationNames{{{
    {ScaleNormalization::None, "none"},
    {ScaleNormalization::ByFirstInvariant, "xi1"},
    {ScaleNormalization::ByArea, "area"}}}};

inline constexpr EnumNames<OffRecipePolicy, 2> kOffRecipePolicyNames{{{
    {OffRecipePolicy::Refuse, "refuse"},
    {OffRecipePolicy::AcceptFlagged, "accept_flagged"}}}};

}  // namespace wish
