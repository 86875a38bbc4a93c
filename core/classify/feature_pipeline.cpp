#include "core/classify/feature_pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/classify/global_descriptors.hpp"
#include "core/classify/laplace_spectrum.hpp"
#include "core/sh/sh_basis.hpp"
#include "core/sh/sh_canonical_frame.hpp"
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
  const FamilyBlocks blocks = family_blocks(spec.family);
  if (blocks.canonical_sh && spec.l_min < 1)
    throw InvalidInputError("feature_spec", "canonical SH coefficients start at degree 1, l_min is " + std::to_string(spec.l_min));
  if (spec.spectrum_count < (blocks.spectrum ? 1 : 0) || spec.spectrum_count > kMaxSpectrumCount)
    throw InvalidInputError("feature_spec", "spectrum_count " + std::to_string(spec.spectrum_count) + " for family " +
                                                to_string(spec.family));
  if (blocks.invariants || blocks.canonical_sh) {
    if (spec.l_min < 0 || spec.l_max < spec.l_min || spec.l_max > kShMaxFitLmax)
      throw InvalidInputError("feature_spec", "invalid range of l: [" + std::to_string(spec.l_min) + ", " +
                                                  std::to_string(spec.l_max) + "]");
    if (spec.scale == ScaleNormalization::ByFirstInvariant && spec.l_max < 1)
      throw InvalidInputError("feature_spec", "normalising by xi(1) needs l_max >= 1");
  }
}

std::vector<int> used_global_indices(const FeatureSpec& spec) {
  std::vector<int> idx;
  if (!family_blocks(spec.family).global) return idx;
  for (int i = 0; i < kGlobalCount; ++i)
    if (!spec.global_scale_free || global_descriptor_is_scale_free(i)) idx.push_back(i);
  return idx;
}

std::vector<std::string> feature_names(const FeatureSpec& spec) {
  std::vector<std::string> names;
  const FamilyBlocks blocks = family_blocks(spec.family);
  if (blocks.invariants)
    for (int l = spec.l_min; l <= spec.l_max; ++l) names.push_back("xi_" + std::to_string(l));
  if (blocks.spectrum)
    for (int i = 1; i <= spec.spectrum_count; ++i) names.push_back("lb_" + std::to_string(i));
  if (blocks.canonical_sh)
    for (auto& n : canonical_sh_feature_names(spec.l_min, spec.l_max)) names.push_back(std::move(n));
  for (int i : used_global_indices(spec)) names.push_back("g_" + global_descriptor_names()[i]);
  return names;
}

namespace {

// The divisor of a length^2 quantity for the spec's scale normalisation (1: none).
double scale_divisor(const ShapeFeatures& features, const FeatureSpec& spec) {
  double divisor = 1;
  if (spec.scale == ScaleNormalization::ByFirstInvariant) {
    if (features.invariants.size() < 2)
      throw InvalidInputError("feature_mismatch", "normalising by xi(1) needs the invariants, the descriptor has none");
    divisor = features.invariants(1);
  }
  if (spec.scale == ScaleNormalization::ByArea) divisor = features.global(kGlobalArea);
  if (!(divisor > 0) || !std::isfinite(divisor))
    throw InvalidInputError("feature_mismatch", "cannot normalise the energies: divisor " + std::to_string(divisor));
  return divisor;
}

// log of a non-negative quantity; a floor keeps exact zeros finite.
double floored_log(double v) { return std::log(std::max(v, std::numeric_limits<double>::min())); }

}  // namespace

Eigen::VectorXd apply_feature_pipeline(const ShapeFeatures& features, const FeatureSpec& spec) {
  const FamilyBlocks blocks = family_blocks(spec.family);
  const bool need_xi = blocks.invariants;
  const bool need_global = blocks.global || ((need_xi || blocks.canonical_sh) && spec.scale == ScaleNormalization::ByArea);
  if (blocks.spectrum && features.laplace_spectrum.size() < spec.spectrum_count)
    throw InvalidInputError("feature_mismatch", "the model uses " + std::to_string(spec.spectrum_count) +
                                                    " Laplace-Beltrami eigenvalues but the descriptor has " +
                                                    std::to_string(features.laplace_spectrum.size()));
  const Eigen::Index canonical_needed = 3 * (sh_count(spec.l_max) - 1);
  if (blocks.canonical_sh && features.canonical_sh.size() < canonical_needed)
    throw InvalidInputError("feature_mismatch", "the model uses canonical SH coefficients up to degree " +
                                                    std::to_string(spec.l_max) + " but the descriptor has " +
                                                    std::to_string(features.canonical_sh.size()) + " of the " +
                                                    std::to_string(canonical_needed) + " values");
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
  const int n_lb = blocks.spectrum ? spec.spectrum_count : 0;
  const int n_csh = blocks.canonical_sh ? 3 * (sh_count(spec.l_max) - sh_count(spec.l_min - 1)) : 0;
  Eigen::VectorXd out(n_xi + n_lb + n_csh + static_cast<int>(globals.size()));
  int at = 0;
  if (need_xi) {
    const double divisor = scale_divisor(features, spec);
    for (int l = spec.l_min; l <= spec.l_max; ++l) {
      const double v = features.invariants(l) / divisor;  // energies are >= 0
      out(at++) = spec.log_transform ? floored_log(v) : v;
    }
  }
  // The spectrum is area-normalised already (scale-free); log as the energies when the spec says so.
  for (int i = 0; i < n_lb; ++i) out(at++) = spec.log_transform ? floored_log(features.laplace_spectrum(i)) : features.laplace_spectrum(i);
  if (n_csh > 0) {
    // Coefficients are lengths: divided by the square root of the length^2 divisor. Degree l starts at value
    // 3 (l^2 - 1) of the flattened degrees 1..Lmax.
    const double divisor = std::sqrt(scale_divisor(features, spec));
    out.segment(at, n_csh) = features.canonical_sh.segment(3 * (sh_count(spec.l_min - 1) - 1), n_csh) / divisor;
    at += n_csh;
  }
  for (std::size_t i = 0; i < globals.size(); ++i) out(at + static_cast<int>(i)) = features.global(globals[i]);
  if (!out.allFinite()) throw InvalidInputError("feature_mismatch", "the feature vector contains NaN or infinity");
  return out;
}

}  // namespace wish
