#pragma once
// ModelInfo (proto/openapi.json, GET /v1/models): a loaded model's name, version, file, classes, descriptor
// settings and full recipe, feature spec and training summary (with the class spectra the web page draws).
// Built once when the service loads a model.

#include <filesystem>

#include <nlohmann/json.hpp>

#include "core/classify/classifier_model.hpp"

namespace wish::wire {

// `file` is the model's path; only its file name is shown. "loaded_at" is now (UTC, ISO 8601).
nlohmann::json model_info_json(const ClassifierModel& model, const std::filesystem::path& file);

}  // namespace wish::wire
