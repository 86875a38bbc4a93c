#pragma once
// One model file as loaded by the registry (includes Eigen through classifier_model.hpp: never include from an
// http_*.cpp file).

#include <cstdint>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "core/classify/classifier_model.hpp"

namespace wish::server {

struct LoadedModel {
  ClassifierModel model;
  std::filesystem::path file;
  std::filesystem::file_time_type mtime{};
  std::uintmax_t size = 0;
  nlohmann::json info;  // ModelInfo, built once at load
};

}  // namespace wish::server
