#include "core/classify/feature_pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/classify/global_descriptors.hpp"
#include "core/common/enum_names.hpp"
#include "core/common/errors.hpp"
#include "core/classify/recipe_names.hpp"

namespace wish {

const char* to_string(FeatureFamily family) { return kFeatureFamilyNames.name(family); }

const char* to_string(ScaleNormalization scale) { return kScaleNormalizationNames.name(scale); }

FeatureFamily feature_family_from_name(const std::string& name) {
  return kFeatureFamilyNames.parse(name, "feature family", "family", "feature_spec");
}

ScaleNormalization scale_normalization_from_name(const std::string& name) {
  return kScaleNormalizationNames.parse(name, "scale normalisation", "scale", "feature_spec");
}

void validate_feature_spec(const FeatureSpec& spec) {
  if (spec.family != FeatureFamily::Global) {
    if (spec.l_min < 0 || spec.l_max < spec.l_min || spec.l_max > 100)
      throw InvalidInputError("feature_spec", "invalid range of l: [" + std::to_string(spec.l_min) + ", " +
                                                  std::to_string(spec.l_max) + "]");
    if (spec.scale == ScaleNormalization::ByFirstInvariant && spec.l_max < 1)
      throw InvalidInputError("feature_spec", "normalising by xi(1) needs l_max >= 1");
  }
}

std::vector<int> used_global_indices(const FeatureSpec& spec) {
  std::vector<int> idx;
  if (spec.family == FeatureFamily::Invariants) return idx;
  for (int i = 0; i < kGlobalCount; ++i)
    if (!spec.global_scale_free || global_descriptor_is_scale_free(i)) idx.push_back(i);
  return idx;
}

std::vector<std::string> feature_names(const FeatureSpec& spec) {
  std::vector<std::string> names;
  if (spec.family != FeatureFamily::Global)
    for (int l = spec.l_min; l <= spec.l_max; ++l) names.push_back("xi_" + std::to_string(l));
  for (int i : used_global_indices(spec)) names.push_back("g_" + global_descriptor_names()[i]);
  return names;
}

Eigen::VectorXd apply_feature_pipeline(const ShapeFeatures& features, const FeatureSpec& spec) {
  const bool need_xi = spec.family != FeatureFamily::Global;
  const bool need_global = spec.family != FeatureFamily::Invariants || (need_xi && spec.scale == ScaleNormalization::ByArea);
  if (need_xi && features.invariants.size() < spec.l_max + 1)
    throw InvalidInputError("feature_mismatch", "the model uses xi(" + std::to_string(spec.l_max) + ") but the descriptor has only " +
                                                    std::to_string(features.invariants.size()) + " invariants (Lmax " +
                                                    std::to_string(features.invariants.size() - 1) + ")");
  if (need_global && features.global.size() != kGlobalCount)
    throw InvalidInputError("feature_mismatch", "the model needs the " + std::to_string(int(kGlobalCount)) +
                                                    " global shape descriptors, got " +
                                                    std::to_string(features.global.size()));
  const std::vector<int> globals = used_global_indices(spec);
  const int n_xi = need_xi ? spec.l_max - spec.l_min + 1 : 0;
  Eigen::VectorXd out(n_xi + static_cast<int>(globals.size()));
  if (need_xi) {
    double divisor = 1;
    if (spec.scale == ScaleNormalization::ByFirstInvariant) divisor = features.invariants(1);
    if (spec.scale == ScaleNormalization::ByArea) divisor = features.global(kGlobalArea);
    if (!(divisor > 0) || !std::isfinite(divisor))
      throw InvalidInputError("feature_mismatch", "cannot normalise the energies: divisor " + std::to_string(divisor));
    for (int l = spec.l_min; l <= spec.l_max; ++l) {
      double v = features.invariants(l) / divisor;
      // log of an energy: energies are >= 0; a floor keeps exact zeros finite.
      if (spec.log_transform) v = std::log(std::max(v, std::numeric_limits<double>::min()));
      out(l - spec.l_min) = v;
    }
  }
  for (std::size_t i = 0; i < globals.size(); ++i) out(n_xi + static_cast<int>(i)) = features.global(globals[i]);
  if (!out.allFinite()) throw InvalidInputError("feature_mismatch", "the feature vector contains NaN or infinity");
  return out;
}

}  // namespace wish
