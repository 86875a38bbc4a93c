#pragma once
// The classifier models of a models directory (*.json), loaded at start and reloaded on SIGHUP or
// POST /v1/admin/reload. A reload builds a complete new snapshot and swaps one shared_ptr, so a request holds the
// snapshot's model it started with until it finishes; a file that fails to load is refused with a log line and the
// previously loaded version from that file stays.
// Eigen-free header: LoadedModel is only forward-declared here (compute_service.cpp sees its definition).

#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace wish::server {

struct LoadedModel;  // defined in loaded_model.hpp

// The model's ModelInfo JSON (proto/openapi.json): name, version, classes, descriptor settings, training summary.
const nlohmann::json& model_info(const LoadedModel& model);
const std::string& model_name(const LoadedModel& model);
// Where `wish train` writes the model's training report: `<model file stem>-report.json` beside the model file
// (core/training/training_report.hpp: grid search, hold-out confusion matrix, per-class scores, losses). It is read
// when asked for (GET /v1/models/{name}/report), not at load: a report is not part of the model.
std::filesystem::path training_report_path(const LoadedModel& model);

struct ReloadReport {
  std::vector<std::string> loaded;  // names of the models in the new snapshot
  struct Refused {
    std::string file, message;
    bool kept_previous = false;
  };
  std::vector<Refused> refused;
  bool ok() const { return refused.empty(); }
  nlohmann::json to_json() const;
};

class ModelRegistry {
 public:
  ModelRegistry(std::filesystem::path directory, std::string default_name);
  ~ModelRegistry();

  // Scans the directory again; serialized (two reloads never interleave). Never throws for a bad file.
  ReloadReport reload();

  // "" -> the default model (named default_name, else the only one). nullptr when not found.
  std::shared_ptr<const LoadedModel> find(const std::string& name) const;
  // The name `find("")` resolves to, or "" when ambiguous / none.
  std::string default_name() const;
  nlohmann::json list_json() const;  // ModelList
  std::size_t size() const;

 private:
  struct Snapshot;
  std::shared_ptr<const Snapshot> snapshot() const;

  std::filesystem::path directory_;
  std::string configured_default_;
  mutable std::mutex snapshot_mutex_;  // guards the pointer only; snapshots are immutable
  std::shared_ptr<const Snapshot> snapshot_;
  std::mutex reload_mutex_;
};

}  // namespace wish::server
