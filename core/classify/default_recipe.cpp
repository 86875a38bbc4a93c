#include "core/classify/default_recipe.hpp"

#include <sstream>

#include "core/classify/feature_pipeline.hpp"  // to_string(FeatureFamily)

namespace wish {

DescriptorRecipe default_training_recipe() {
  DescriptorRecipe recipe;
  recipe.map.method = MapMethod::Cmcf;
  recipe.map.fallback = true;
  recipe.map.canonical.method = CanonicalMap::Isometric;
  recipe.sh.lmax = 10;
  recipe.sh.regularization = 1e-1;
  recipe.sh.weighting = FitWeighting::Area;
  recipe.sh.sampling = FitSampling::Surface;
  recipe.features.family = FeatureFamily::Combined;
  recipe.features.l_min = 1;
  recipe.features.l_max = recipe.sh.lmax;
  recipe.features.scale = ScaleNormalization::None;
  recipe.features.log_transform = true;
  recipe.features.spectrum_count = 0;  // combined has no spectrum block (the legacy 0 keeps the file's version)
  recipe.off_recipe = OffRecipePolicy::Refuse;
  return recipe;
}

std::string recipe_summary(const DescriptorRecipe& recipe) {
  std::ostringstream out;
  out << to_string(recipe.map.method) << " map";
  if (recipe.map.canonical.method != CanonicalMap::None) out << ", canonical " << to_string(recipe.map.canonical.method);
  out << ", Lmax " << recipe.sh.lmax << ", nu " << recipe.sh.regularization
      << (recipe.features.log_transform ? ", log" : "") << ", features " << to_string(recipe.features.family);
  return out.str();
}

}  // namespace wish
