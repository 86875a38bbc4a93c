#pragma once
// The feature pipeline of docs/design/classification.md, recorded in the model (FeatureSpec) and replayed exactly at
// prediction: select xi(l) for l in [l_min, l_max] (default 1..Lmax: xi(0) depends on the translation),
// optional scale normalisation (xi(l)/xi(1) or xi(l)/area; xi scales as length^2), optional log, then the
// global descriptors when the family asks for them. The z-score scaler (standard_scaler.hpp) comes after.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/classify/classifier_model.hpp"
#include "core/sh/sh_lmax_range.hpp"

namespace wish {

// The smallest Lmax features can be built from: they start at degree 1 (xi(0) is the energy of the centroid, which
// moves with the mesh; the canonical SH coefficients start at degree 1 too), so a fit to Lmax 0 leaves no feature.
// The bound of `wish train --lmax` and of a service request's lmax, with the fit's kShMaxFitLmax above.
inline constexpr int kMinFeatureLmax = 1;

const char* to_string(FeatureFamily family);         // "invariants" | "global" | "combined"
const char* to_string(ScaleNormalization scale);     // "none" | "xi1" | "area"
FeatureFamily feature_family_from_name(const std::string& name);          // throws InvalidInputError
ScaleNormalization scale_normalization_from_name(const std::string& name);  // throws InvalidInputError

// Throws InvalidInputError("feature_spec") for an inconsistent spec (l range, ...).
void validate_feature_spec(const FeatureSpec& spec);
// Names of the pipeline's output columns ("xi_1", ..., "g_sphericity", ...), in order.
std::vector<std::string> feature_names(const FeatureSpec& spec);
// Indices into global_shape_descriptors() used by `spec` (empty for Invariants).
std::vector<int> used_global_indices(const FeatureSpec& spec);
// The unscaled feature vector. Throws InvalidInputError("feature_mismatch") when `features` lack what is needed.
Eigen::VectorXd apply_feature_pipeline(const ShapeFeatures& features, const FeatureSpec& spec);

}  // namespace wish
