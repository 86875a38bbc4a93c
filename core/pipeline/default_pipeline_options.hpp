#pragma once
// The descriptor settings every front end starts from when the user names none: `wish describe`, `wish map`, the
// service's /v1/describe and the page. They are the default training recipe's map and fit
// (core/classify/default_recipe.hpp), so that one chain decides every mesh's map by default (issue 37 item 2):
// a mesh described with no options has the descriptor a model trained with no options uses, and `wish describe
// --csv` feeds `wish train CSV` descriptors of the recipe train records. Classification always uses the model's own
// recipe (options_for_recipe), whatever this default is.
//
// The paper's map and fit (Willmore flow, the chain's own map, Lmax 15, nu 1e-5 — the closest fit and the most
// faithful reconstruction) stay one option away: --method willmore --canonical none --lmax 15 --regularization 1e-5.

#include "core/pipeline/pipeline.hpp"

namespace wish {

// Map and SH fit of default_training_recipe(); reading, repair, features and reconstruction at PipelineOptions{}.
PipelineOptions default_pipeline_options();

}  // namespace wish
