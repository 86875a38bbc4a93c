#pragma once
// The classification recipe of `wish train` when the user names none: ONE value, read by every edge that needs it
// (cli/cmd_train.cpp's option defaults, its help footer, `wish describe`'s footer; issue 37 item 5), never restated.
// The bundled model (scripts/make-default-model.sh) spells its own recipe out and records it in its file: classify
// always uses the model's recipe, whatever this default becomes.
//
// Chosen by nested-CV accuracy and by the meshes each recipe keeps (docs/accuracy.md, "Issue 37"):
//   map        cMCF chain (every fallback after it), then the canonical isometric map (canonical_map.hpp) from
//              whichever attempt gave the chain's bijective map — one definition for every mesh, so no mesh is lost
//              to its path (a relaxation its budget stopped is kept and reported: canonical_converged false);
//   SH fit     Lmax 10, ν = 1e-1 in the paper's units (penalty 1e-5 l²(l+1)² at unit-sum weights, 10⁴ × the fit's own
//              default: it damps degrees above ~9, and the smoother ξ classify better), area weights, samples over the
//              surface (surface_quadrature.hpp: the same integral at every resolution, issue 37 item 3; max |Δ log ξ|
//              under one midpoint subdivision of 8 real meshes 0.005–0.085, mean 0.042, against 0.043–0.328, mean
//              0.153, at the vertices; nested CV ξ alone +1.4 to +1.8 points, combined −1.2 to 0, docs/accuracy.md);
//   features   ξ(1..10), log, no scale normalisation, plus the global shape descriptors (family combined: better than ξ
//              alone on every labelled set measured, issue 37 item 6 / issue 38);
//   policy     off-recipe maps refused (with the canonical map only a relaxation that could not run is off-recipe).

#include <string>

#include "core/classify/descriptor_recipe.hpp"

namespace wish {

DescriptorRecipe default_training_recipe();

// One line naming the recipe's choices, for help texts: e.g. "cmcf map, canonical isometric, Lmax 10, nu 1e-1,
// log, features combined".
std::string recipe_summary(const DescriptorRecipe& recipe);

}  // namespace wish
