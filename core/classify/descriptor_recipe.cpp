#include "core/classify/descriptor_recipe.hpp"

#include <algorithm>
#include <cmath>

#include "core/classify/descriptor_recipe_codec.hpp"

#include "core/common/enum_names.hpp"
#include "core/common/errors.hpp"
#include "core/classify/feature_pipeline.hpp"
#include "core/classify/laplace_spectrum.hpp"
#include "core/classify/recipe_names.hpp"
#include "core/spherical_map/flow_step_cap.hpp"

namespace wish {

const char* to_string(OffRecipePolicy policy) { return kOffRecipePolicyNames.name(policy); }

OffRecipePolicy off_recipe_policy_from_name(const std::string& name) {
  return kOffRecipePolicyNames.parse(name, "off-recipe policy", "off_recipe");
}

void validate_recipe(const DescriptorRecipe& r, const std::string& code) {
  if (r.sh.lmax < kShMinFitLmax || r.sh.lmax > kShMaxFitLmax)
    throw InvalidInputError(code, "recipe sh.lmax " + std::to_string(r.sh.lmax) + " is out of the SH fit's range " +
                                      std::to_string(kShMinFitLmax) + ".." + std::to_string(kShMaxFitLmax));
  if (r.features.l_min < 0 || r.features.l_min > r.features.l_max)
    throw InvalidInputError(code, "recipe features use xi(" + std::to_string(r.features.l_min) + ".." +
                                      std::to_string(r.features.l_max) + "), an empty or negative range");
  const FamilyBlocks blocks = family_blocks(r.features.family);
  if ((blocks.invariants || blocks.canonical_sh) && r.features.l_max > r.sh.lmax)
    throw InvalidInputError(code, std::string("recipe features use ") + (blocks.invariants ? "xi(" : "SH coefficients of degree ") +
                                      std::to_string(r.features.l_max) + (blocks.invariants ? ")" : "") +
                                      " but descriptors are fitted up to Lmax " + std::to_string(r.sh.lmax));
  if (blocks.canonical_sh && r.features.l_min < 1)
    throw InvalidInputError(code, "recipe features use canonical SH coefficients from degree " +
                                      std::to_string(r.features.l_min) + "; degree 0 is the position, l_min must be >= 1");
  if (r.features.spectrum_count < (blocks.spectrum ? 1 : 0) || r.features.spectrum_count > kMaxSpectrumCount)
    throw InvalidInputError(code, "recipe features.spectrum_count " + std::to_string(r.features.spectrum_count) + " for family " +
                                      to_string(r.features.family) + ": must be in " + (blocks.spectrum ? "1" : "0") + ".." +
                                      std::to_string(kMaxSpectrumCount));
}

RecipeConformance check_recipe(const DescriptorRecipe& recipe, const SphericalMapResult& map) {
  RecipeConformance c;
  c.recipe_method = recipe.map.method;
  c.method_used = map.method_used;
  c.attempts = static_cast<int>(map.attempts.size());
  c.canonical = recipe.map.canonical.method;
  c.canonical_stop = map.canonical.stop;
  c.canonical_converged = map.canonical.converged;
  c.canonical_excess = map.canonical.energy - recipe.map.canonical.energy.minimum();
  if (recipe.map.canonical.method != CanonicalMap::None)
    // One definition for every map (issue 37): the descriptor is computed on the canonical relaxation of the chain's
    // bijective map, whichever attempt of the chain gave its start. It is the recipe's descriptor when the
    // relaxation ran from a valid start (no mesh is lost to its path); whether it reached the minimiser within its
    // budget is reported beside it (canonical_converged, canonical_excess): the path-dependence that remains.
    c.match = map.canonical.method == recipe.map.canonical.method && map.canonical.stop != CanonicalMapStop::NotRun &&
              map.canonical.stop != CanonicalMapStop::Reverted && std::isfinite(map.canonical.energy);
  else
    c.match = map.method_used == recipe.map.method;
  return c;
}

void enforce_recipe_policy(const DescriptorRecipe& recipe, const RecipeConformance& c, const std::string& model_name) {
  if (c.match || recipe.off_recipe == OffRecipePolicy::AcceptFlagged) return;
  const std::string used = to_string(c.method_used), wanted = to_string(c.recipe_method);
  if (c.canonical != CanonicalMap::None)
    throw WishError(ErrorCategory::Unmappable, "off_recipe",
                    std::string("the canonical map was not reached (relaxation stopped: ") + to_string(c.canonical_stop) +
                        ", start from the " + used + " map), and model '" + model_name +
                        "' refuses descriptors of other maps (off_recipe: refuse)",
                    {{"method_used", used},
                     {"canonical", to_string(c.canonical)},
                     {"canonical_stop", to_string(c.canonical_stop)},
                     {"attempts", static_cast<std::int64_t>(c.attempts)},
                     {"model", model_name}});
  throw WishError(ErrorCategory::Unmappable, "off_recipe",
                  "the spherical map was made by the " + used + " fallback, but model '" + model_name +
                      "' was trained on " + wanted + " maps and its policy refuses other methods (off_recipe: refuse)",
                  {{"method_used", used},
                   {"recipe_method", wanted},
                   {"attempts", static_cast<std::int64_t>(c.attempts)},
                   {"model", model_name}});
}

namespace {

// The highest version among the fields that differ from their legacy value (descriptor_recipe_codec.hpp).
struct VersionOfFields {
  int version = 1;
  template <class T> void field(const char*, const T&) {}
  // A family added after version 1 makes the file of its version (an older reader refuses it by number).
  void field(const char*, const FeatureFamily& family) { version = std::max(version, feature_family_version(family)); }
  template <class F> void group(const char*, F&& fill) { fill(*this); }
  template <class T> void added(int since, const char*, const T& value, const T& legacy) {
    if (!(value == legacy)) version = std::max(version, since);
  }
  template <class F, class T> void added_group(int since, const char*, F&&, const T& target, const T& legacy) {
    if (!(target == legacy)) version = std::max(version, since);
  }
  template <class T> void retired(const char*, int, const T&) {}
  void derived(const char*) {}
};

}  // namespace

int recipe_version_of(const DescriptorRecipe& recipe) {
  VersionOfFields v;
  visit_recipe(v, recipe);
  return v.version;
}

int model_steps(const DescriptorRecipe& recipe) {
  return flow_step_cap(recipe.map);
}

}  // namespace wish
