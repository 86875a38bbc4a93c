#pragma once
// The descriptor recipe (issue 12): everything that changes the feature vector a model sees, in one versioned,
// typed value — the spherical-map method and all its options, the SH fit (Lmax, nu, weighting, solver), the feature
// pipeline (which xi(l), scale normalisation, log, feature family) — plus the model's policy for a descriptor whose
// map came from another method than the recipe's (a fallback attempt of the chain). The CLI builds it from its
// flags, the model file stores it (model_file.cpp, format version 2, recipe_version), the pipeline and the server compute with it
// and check every result against it (check_recipe): a descriptor computed another way is never fed to a model
// silently — it is refused, or accepted with recipe_match = false in the result, as the model's policy says.

#include <string>

#include "core/classify/laplace_spectrum.hpp"
#include "core/sh/sh_descriptor.hpp"
#include "core/spherical_map/spherical_map.hpp"

namespace wish {

// Which features the SVM sees (docs/accuracy.md has the table that measures them). Invariants: the paper's xi(l);
// Global: rotation-invariant shape measures of the mesh (global_descriptors.hpp); Spectrum: ShapeDNA, the first
// eigenvalues of the Laplace-Beltrami operator (laplace_spectrum.hpp; intrinsic, bending-invariant); CanonicalSh:
// the SH coefficients in the first-order-ellipsoid frame (core/sh/sh_canonical_frame.hpp; keeps the phases xi
// discards). The later families were added in recipe version 4 (issue 38).
enum class FeatureFamily { Invariants, Global, Combined, Spectrum, SpectrumGlobal, CanonicalSh, CanonicalShGlobal, All };

// The blocks of a family's feature vector, in the order the pipeline writes them: xi(l_min..l_max), the spectrum
// (lb_1..lb_count), the canonical SH coefficients of degrees l_min..l_max, the global descriptors.
struct FamilyBlocks {
  bool invariants = false, spectrum = false, canonical_sh = false, global = false;
};
constexpr FamilyBlocks family_blocks(FeatureFamily family) {
  switch (family) {
    case FeatureFamily::Invariants: return {true, false, false, false};
    case FeatureFamily::Global: return {false, false, false, true};
    case FeatureFamily::Combined: return {true, false, false, true};
    case FeatureFamily::Spectrum: return {false, true, false, false};
    case FeatureFamily::SpectrumGlobal: return {false, true, false, true};
    case FeatureFamily::CanonicalSh: return {false, false, true, false};
    case FeatureFamily::CanonicalShGlobal: return {false, false, true, true};
    case FeatureFamily::All: return {true, true, true, true};
  }
  return {};
}
// The recipe version that introduced the family (1 for the paper's three, 4 for the others).
constexpr int feature_family_version(FeatureFamily family) {
  return family == FeatureFamily::Invariants || family == FeatureFamily::Global || family == FeatureFamily::Combined ? 1 : 4;
}
enum class ScaleNormalization { None, ByFirstInvariant, ByArea };  // xi(l)/xi(1), or xi(l)/surface area

struct FeatureSpec {
  FeatureFamily family = FeatureFamily::Invariants;
  int l_min = 1, l_max = 5;                 // which xi(l) are used (inclusive)
  ScaleNormalization scale = ScaleNormalization::None;
  bool log_transform = false;               // log(x) of the (normalised) energies
  bool global_scale_free = false;           // Global/Combined: only the scale-free global descriptors
  // Families with the spectrum: how many Laplace-Beltrami eigenvalues (lb_1..lb_n); unused by the others.
  // Recipe version 4; files of older versions read the legacy 0 (no spectrum).
  int spectrum_count = kDefaultSpectrumCount;
  bool operator==(const FeatureSpec&) const = default;
};

// What to do with a descriptor whose map was made by another method than the recipe's (the fallback chain ended
// on cMCF or the linear map for a Willmore recipe, ...): its xi are on another scale of Möbius/area distortion, so
// the SVM was not trained on such vectors.
enum class OffRecipePolicy {
  Refuse,         // classify: error "off_recipe" (422); training: the mesh is counted as refused
  AcceptFlagged,  // classify: predict, with recipe_match = false in the result; training: kept, counted as flagged
};
const char* to_string(OffRecipePolicy policy);                    // "refuse" | "accept_flagged"
OffRecipePolicy off_recipe_policy_from_name(const std::string& name);  // throws InvalidInputError

struct DescriptorRecipe {
  // Version of the recipe's content (fields and their meaning); stored in the model file next to the recipe.
  // Which version introduced which field is listed once, in descriptor_recipe_codec.hpp (1: the first; 2: the
  // operator, flow budget and area correction; 3: the chain budget and cMCF's stall patience; 5: the canonical map and the SH fit's sampling). Files of every
  // version up to kVersion load (model_file.cpp); a newer one is refused, as is any key this build does not know.
  static constexpr int kVersion = 5;
  // From this version on a file's version is computed from its fields (recipe_version_of) and its keys are exactly
  // that version's; older files may carry keys of later versions (written before the version table existed).
  static constexpr int kFirstComputedVersion = 3;
  SphericalMapOptions map;   // method, fallback chain switch, flow parameters, verification bounds
  ShFitOptions sh;           // lmax, regularization nu, weighting, solver
  FeatureSpec features;      // xi(l_min..l_max), scale normalisation, log, family
  OffRecipePolicy off_recipe = OffRecipePolicy::Refuse;
  bool operator==(const DescriptorRecipe&) const = default;

  // ByArea normalisation needs the mesh area, which is one of the global descriptors.
  bool needs_global_features() const {
    const FamilyBlocks b = family_blocks(features.family);
    return b.global || ((b.invariants || b.canonical_sh) && features.scale == ScaleNormalization::ByArea);
  }
  bool uses_invariants() const { return family_blocks(features.family).invariants; }
  // xi(1) normalises the canonical coefficients too (ScaleNormalization::ByFirstInvariant).
  bool needs_invariants() const {
    const FamilyBlocks b = family_blocks(features.family);
    return b.invariants || (b.canonical_sh && features.scale == ScaleNormalization::ByFirstInvariant);
  }
  bool needs_laplace_spectrum() const { return family_blocks(features.family).spectrum; }
  bool needs_canonical_sh() const { return family_blocks(features.family).canonical_sh; }
};

// The recipe version a file of this recipe gets: the highest version that introduced a field whose value differs
// from its legacy value (the behaviour before the field existed); at least 1. The oldest reader that computes the
// same descriptor from the file can read it.
int recipe_version_of(const DescriptorRecipe& recipe);

// Throws InvalidInputError(code, ...) when the parts disagree (features use xi(l) above sh.lmax, bad l range, a
// spectrum count out of range, or none for a family with the spectrum).
void validate_recipe(const DescriptorRecipe& recipe, const std::string& code = "invalid_recipe");

// The flow step cap of the recipe's map method (what a request's `steps` is compared with; the linear map has
// none and reports the Willmore cap).
int model_steps(const DescriptorRecipe& recipe);

// How one computed descriptor relates to a recipe.
struct RecipeConformance {
  // The descriptor is the recipe's: for a canonical recipe, the canonical relaxation ran from the chain's map
  // (whatever attempt gave its start; converged or not, see below); otherwise the map was made by the recipe's method.
  bool match = true;
  CanonicalMap canonical = CanonicalMap::None;             // the recipe's canonical map
  CanonicalMapStop canonical_stop = CanonicalMapStop::NotRun;  // how this map's relaxation ended
  bool canonical_converged = false;  // the relaxation reached the minimiser (else: stopped at its budget or cap)
  double canonical_excess = 0;       // E − min E of the returned map (0: a round, isometric map)
  MapMethod recipe_method = MapMethod::Willmore;
  MapMethod method_used = MapMethod::Willmore;
  int attempts = 1;                       // attempts of the map chain (1: the first attempt gave the map)
};
RecipeConformance check_recipe(const DescriptorRecipe& recipe, const SphericalMapResult& map);

// Throws WishError(Unmappable, "off_recipe", ...) naming both methods when `c` does not match and the policy
// refuses; otherwise returns.
void enforce_recipe_policy(const DescriptorRecipe& recipe, const RecipeConformance& c, const std::string& model_name);

}  // namespace wish
