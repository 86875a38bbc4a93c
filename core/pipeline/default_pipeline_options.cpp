#include "core/pipeline/default_pipeline_options.hpp"

#include "core/classify/default_recipe.hpp"

namespace wish {

PipelineOptions default_pipeline_options() {
  // options_for_recipe is the one translation of a recipe into pipeline options (it also decides prefer_method);
  // only its map and fit are taken: a description does not need the model's feature blocks.
  const PipelineOptions recipe = options_for_recipe(default_training_recipe());
  PipelineOptions options;
  options.map = recipe.map;
  options.sh = recipe.sh;
  return options;
}

}  // namespace wish
