// The descriptor recipe and its off-recipe policy (issue 12): a descriptor whose map came from another method
// than the model's is refused or predicted-with-a-flag as the model's stored policy says.
#include <gtest/gtest.h>

#include "core/classify/default_recipe.hpp"
#include "core/classify/descriptor_recipe.hpp"
#include "core/classify/feature_pipeline.hpp"
#include "core/common/errors.hpp"
#include "core/pipeline/pipeline.hpp"
#include "tests/classify/classify_test_data.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

SphericalMapResult map_made_by(MapMethod method, int attempts) {
  SphericalMapResult map;
  map.method_used = method;
  map.attempts.resize(static_cast<std::size_t>(attempts));
  return map;
}

TEST(DescriptorRecipe, ConformanceComparesTheMethodThatMadeTheMap) {
  DescriptorRecipe recipe;
  recipe.map.method = MapMethod::Willmore;
  const RecipeConformance same = check_recipe(recipe, map_made_by(MapMethod::Willmore, 2));
  EXPECT_TRUE(same.match);  // "more steps" of the same flow is still the recipe's method
  EXPECT_EQ(same.attempts, 2);
  const RecipeConformance other = check_recipe(recipe, map_made_by(MapMethod::Cmcf, 4));
  EXPECT_FALSE(other.match);
  EXPECT_EQ(other.method_used, MapMethod::Cmcf);
  EXPECT_EQ(other.recipe_method, MapMethod::Willmore);
}

// A canonical recipe (issue 37): whichever attempt made the start, the relaxed map is the recipe's; a relaxation its
// budget stopped is kept (match) and says so (canonical_converged false, its excess energy); one that could not run
// (the chain's map was kept as it was) is off-recipe.
TEST(DescriptorRecipe, ACanonicalRecipeKeepsEveryRelaxedMapAndReportsConvergence) {
  DescriptorRecipe recipe;
  recipe.map.method = MapMethod::Cmcf;
  recipe.map.canonical.method = CanonicalMap::Isometric;
  auto relaxed = [](MapMethod start, CanonicalMapStop stop, double energy) {
    SphericalMapResult map = map_made_by(start, 3);
    map.canonical.method = CanonicalMap::Isometric;
    map.canonical.stop = stop;
    map.canonical.converged = stop == CanonicalMapStop::Converged;
    map.canonical.energy = energy;
    return map;
  };
  const RecipeConformance converged = check_recipe(recipe, relaxed(MapMethod::Progressive, CanonicalMapStop::Converged, 4.5));
  EXPECT_TRUE(converged.match);
  EXPECT_TRUE(converged.canonical_converged);
  EXPECT_NEAR(converged.canonical_excess, 0.5, 1e-12);  // symmetric Dirichlet's minimum is 4
  const RecipeConformance stopped = check_recipe(recipe, relaxed(MapMethod::Linear, CanonicalMapStop::TimeBudget, 1e6));
  EXPECT_TRUE(stopped.match);
  EXPECT_FALSE(stopped.canonical_converged);
  EXPECT_NO_THROW(enforce_recipe_policy(recipe, stopped, "m"));
  for (const CanonicalMapStop not_run : {CanonicalMapStop::NotRun, CanonicalMapStop::Reverted}) {
    const RecipeConformance c = check_recipe(recipe, relaxed(MapMethod::Cmcf, not_run, 10));
    EXPECT_FALSE(c.match) << to_string(not_run);
    EXPECT_THROW(enforce_recipe_policy(recipe, c, "m"), WishError);
  }
}

TEST(DescriptorRecipe, RefusePolicyThrowsOffRecipeWithBothMethods) {
  DescriptorRecipe recipe;
  recipe.off_recipe = OffRecipePolicy::Refuse;
  const RecipeConformance other = check_recipe(recipe, map_made_by(MapMethod::Linear, 5));
  try {
    enforce_recipe_policy(recipe, other, "m");
    FAIL() << "an off-recipe map was accepted by a refusing recipe";
  } catch (const WishError& e) {
    EXPECT_EQ(e.code(), "off_recipe");
    EXPECT_EQ(e.category(), ErrorCategory::Unmappable);
    EXPECT_NE(std::string(e.what()).find("linear"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("willmore"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(enforce_recipe_policy(recipe, check_recipe(recipe, map_made_by(MapMethod::Willmore, 1)), "m"));
  recipe.off_recipe = OffRecipePolicy::AcceptFlagged;
  EXPECT_NO_THROW(enforce_recipe_policy(recipe, other, "m"));
}

TEST(DescriptorRecipe, PolicyNamesRoundTripAndUnknownIsRefused) {
  for (auto p : {OffRecipePolicy::Refuse, OffRecipePolicy::AcceptFlagged})
    EXPECT_EQ(off_recipe_policy_from_name(to_string(p)), p);
  EXPECT_THROW((void)off_recipe_policy_from_name("maybe"), InvalidInputError);
}

TEST(DescriptorRecipe, ValidationRefusesFeaturesBeyondTheFit) {
  DescriptorRecipe recipe;
  recipe.sh.lmax = 5;
  recipe.features.l_max = 6;
  EXPECT_THROW(validate_recipe(recipe), InvalidInputError);
  recipe.features.family = FeatureFamily::Global;  // no xi used: any Lmax will do
  EXPECT_NO_THROW(validate_recipe(recipe));
}

// End to end on a real map: an ellipsoid described with the model's recipe (a first-attempt Willmore map), then
// the same descriptor as if the chain had ended on cMCF. The refusing model refuses it; the accepting one predicts
// exactly what it predicts from those features, with recipe_match false.
TEST(DescriptorRecipe, ClassifyRefusesOrFlagsAnOffRecipeMap) {
  auto opts = testing::quick_train_options();
  opts.nested_repeats = 0;
  opts.recipe.sh.lmax = 8;
  opts.recipe.off_recipe = OffRecipePolicy::Refuse;
  const auto samples = testing::synthetic_samples(2, 10, 5);
  const ClassifierModel refusing = train_classifier(samples, opts).model;
  opts.recipe.off_recipe = OffRecipePolicy::AcceptFlagged;
  const ClassifierModel accepting = train_classifier(samples, opts).model;

  PipelineResult described = describe_mesh(testing::make_ellipsoid(1.0, 0.8, 0.6, 3), options_for_recipe(refusing.recipe()));
  ASSERT_EQ(described.map.method_used, MapMethod::Willmore);

  PipelineResult on_recipe = described;
  classify_described(on_recipe, refusing);
  ASSERT_TRUE(on_recipe.recipe.has_value());
  EXPECT_TRUE(on_recipe.recipe->match);
  ASSERT_TRUE(on_recipe.prediction.has_value());

  PipelineResult fallback = described;
  fallback.map.method_used = MapMethod::Cmcf;  // what the chain reports when cMCF made the map
  PipelineResult refused = fallback;
  try {
    classify_described(refused, refusing);
    FAIL() << "the refusing model predicted from a cMCF map";
  } catch (const WishError& e) {
    EXPECT_EQ(e.code(), "off_recipe");
  }
  EXPECT_FALSE(refused.prediction.has_value());

  PipelineResult flagged = fallback;
  classify_described(flagged, accepting);
  ASSERT_TRUE(flagged.recipe.has_value());
  EXPECT_FALSE(flagged.recipe->match);
  EXPECT_EQ(flagged.recipe->method_used, MapMethod::Cmcf);
  ASSERT_TRUE(flagged.prediction.has_value());
  EXPECT_EQ(flagged.prediction->label, accepting.predict(described.features).label);
  EXPECT_EQ(flagged.prediction->probabilities, accepting.predict(described.features).probabilities);
}

}  // namespace
}  // namespace wish

namespace wish {
namespace {

// The default training recipe is one core value (default_recipe.hpp): valid as it stands, of the current recipe
// version (it uses the canonical map), and the help texts' summary names what it is.
TEST(DefaultTrainingRecipe, IsValidCanonicalAndNamedInItsSummary) {
  const DescriptorRecipe r = default_training_recipe();
  EXPECT_NO_THROW(validate_recipe(r));
  EXPECT_EQ(r.map.canonical.method, CanonicalMap::Isometric);
  EXPECT_EQ(r.features.l_max, r.sh.lmax);
  EXPECT_EQ(recipe_version_of(r), DescriptorRecipe::kVersion);
  EXPECT_TRUE(r.needs_global_features());  // combined: xi and the global descriptors
  const std::string summary = recipe_summary(r);
  for (const std::string& part : {std::string(to_string(r.map.method)), std::string("canonical isometric"),
                                 "Lmax " + std::to_string(r.sh.lmax), std::string(to_string(r.features.family))})
    EXPECT_NE(summary.find(part), std::string::npos) << summary << " lacks " << part;
}

}  // namespace
}  // namespace wish
