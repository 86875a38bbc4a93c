#include "server/model_registry.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <fstream>
#include <map>

#include <spdlog/spdlog.h>

#include "core/classify/feature_pipeline.hpp"
#include "server/loaded_model.hpp"
#include "wire/model_json.hpp"

namespace wish::server {

struct ModelRegistry::Snapshot {
  std::map<std::string, std::shared_ptr<const LoadedModel>> by_name;
  std::map<std::string, std::shared_ptr<const LoadedModel>> by_file;  // file name -> model
  std::string default_name;
};

const nlohmann::json& model_info(const LoadedModel& model) { return model.info; }
const std::string& model_name(const LoadedModel& model) { return model.model.name(); }
std::filesystem::path training_report_path(const LoadedModel& model) {
  return model.file.parent_path() / (model.file.stem().string() + "-report.json");
}

nlohmann::json ReloadReport::to_json() const {
  nlohmann::json out{{"loaded", loaded}, {"refused", nlohmann::json::array()}, {"models", loaded.size()}};
  for (const auto& r : refused)
    out["refused"].push_back({{"file", r.file}, {"message", r.message}, {"kept_previous", r.kept_previous}});
  return out;
}

ModelRegistry::ModelRegistry(std::filesystem::path directory, std::string default_name)
    : directory_(std::move(directory)), configured_default_(std::move(default_name)),
      snapshot_(std::make_shared<const Snapshot>()) {}

ModelRegistry::~ModelRegistry() = default;

std::shared_ptr<const ModelRegistry::Snapshot> ModelRegistry::snapshot() const {
  std::lock_guard lock(snapshot_mutex_);
  return snapshot_;
}

namespace {
// A readable JSON object with no "format" member: some other JSON (a training report), not a broken model.
bool is_other_json(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  const nlohmann::json doc = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  return doc.is_object() && !doc.contains("format");
}
}  // namespace

ReloadReport ModelRegistry::reload() {
  std::lock_guard reload_lock(reload_mutex_);
  const auto previous = snapshot();
  auto next = std::make_shared<Snapshot>();
  ReloadReport report;

  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(directory_, ec))
    if (entry.is_regular_file() && entry.path().extension() == ".json") files.push_back(entry.path());
  if (ec) {
    spdlog::error("models: cannot read directory {}: {}; keeping the {} loaded model(s)", directory_.string(),
                  ec.message(), previous->by_name.size());
    report.refused.push_back({directory_.string(), "cannot read directory: " + ec.message(), true});
    for (const auto& [name, m] : previous->by_name) report.loaded.push_back(name);
    return report;  // the previous snapshot stays as it is
  }
  std::sort(files.begin(), files.end());  // deterministic: on a duplicate name, the first file wins

  for (const auto& path : files) {
    const std::string file = path.filename().string();
    std::shared_ptr<const LoadedModel> model;
    const auto old = previous->by_file.find(file);
    std::error_code stat_ec;
    const auto mtime = std::filesystem::last_write_time(path, stat_ec);
    const auto size = std::filesystem::file_size(path, stat_ec);
    if (!stat_ec && old != previous->by_file.end() && old->second->mtime == mtime && old->second->size == size) {
      model = old->second;  // unchanged: keep the very same object
    } else if (is_other_json(path)) {
      // `wish train` writes <model>-report.json beside the model: a JSON object without a "format" is not a model
      // file that failed, so it is skipped without an error (a file that claims a format and fails is refused).
      spdlog::debug("models: skipped {}: not a model file (no \"format\" member)", file);
      continue;
    } else {
      try {
        auto loaded = std::make_shared<LoadedModel>(LoadedModel{ClassifierModel::load(path), path, mtime, size, {}});
        loaded->info = wire::model_info_json(loaded->model, path);
        model = std::move(loaded);
        spdlog::info("models: loaded '{}' version {} from {}", model->model.name(), model->model.version(), file);
      } catch (const std::exception& e) {
        const bool keep = old != previous->by_file.end();
        spdlog::error("models: refused {}: {}{}", file, e.what(),
                      keep ? "; keeping the previously loaded version" : "");
        report.refused.push_back({file, e.what(), keep});
        if (!keep) continue;
        model = old->second;
      }
    }
    const std::string& name = model->model.name();
    if (next->by_name.count(name)) {
      const std::string msg = "model name '" + name + "' already loaded from " +
                              next->by_name[name]->file.filename().string();
      spdlog::error("models: refused {}: {}", file, msg);
      report.refused.push_back({file, msg, false});
      continue;
    }
    next->by_name[name] = model;
    next->by_file[file] = model;
  }

  if (next->by_name.count(configured_default_)) next->default_name = configured_default_;
  else if (next->by_name.size() == 1) next->default_name = next->by_name.begin()->first;
  for (const auto& [name, m] : next->by_name) report.loaded.push_back(name);
  spdlog::info("models: {} model(s) loaded from {} ({} refused); default: {}", next->by_name.size(),
               directory_.string(), report.refused.size(), next->default_name.empty() ? "none" : next->default_name);
  {
    std::lock_guard lock(snapshot_mutex_);
    snapshot_ = std::move(next);
  }
  return report;
}

std::shared_ptr<const LoadedModel> ModelRegistry::find(const std::string& name) const {
  const auto snap = snapshot();
  const std::string& key = name.empty() ? snap->default_name : name;
  const auto it = snap->by_name.find(key);
  return it == snap->by_name.end() ? nullptr : it->second;
}

std::string ModelRegistry::default_name() const { return snapshot()->default_name; }

nlohmann::json ModelRegistry::list_json() const {
  const auto snap = snapshot();
  nlohmann::json list = nlohmann::json::array();
  for (const auto& [name, m] : snap->by_name) {
    nlohmann::json info = m->info;
    info["is_default"] = name == snap->default_name;
    list.push_back(std::move(info));
  }
  return {{"models", std::move(list)},
          {"default", snap->default_name.empty() ? nlohmann::json(nullptr) : nlohmann::json(snap->default_name)}};
}

std::size_t ModelRegistry::size() const { return snapshot()->by_name.size(); }

}  // namespace wish::server
