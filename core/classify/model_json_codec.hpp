#pragma once
// The JSON of the model file's parts that other documents show too: the descriptor recipe (every field, listed
// once in descriptor_recipe_codec.hpp) and the per-class spectra. Written by the model file (model_file.cpp) and
// reused by the wire library's model view (wire/model_json.hpp, GET /v1/models), so each is encoded in one place.
// The one core header that exposes nlohmann::json: the model file is core's own persisted format.

#include <vector>

#include <nlohmann/json.hpp>

#include "core/classify/classifier_model.hpp"  // ClassSpectrum, DescriptorRecipe

namespace wish {

// payload.recipe: {"recipe_version", "map", "sh", "features", "off_recipe"}.
nlohmann::json recipe_to_json(const DescriptorRecipe& recipe);
// training.class_spectra: [{"label", "count", "log_xi_mean": [ln xi(1..Lmax)], "log_xi_std": [...]}].
nlohmann::json class_spectra_to_json(const std::vector<ClassSpectrum>& spectra);

}  // namespace wish
