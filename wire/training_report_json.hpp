#pragma once
// The training report (TrainingReport in proto/openapi.json, GET /v1/models/{name}/report; written by `wish train
// --report` beside the model as <model>-report.json): docs/design/classification.md's "Report like Table 1" — class counts and
// losses, features, the grid (C × γ mean/std accuracy, rows C, columns γ), held-out test (confusion matrix: rows
// true class, columns predicted; per-class precision/recall/F1), nested CV. Accuracies are fractions in [0, 1].

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/classify/feature_pipeline.hpp"
#include "core/training/dataset.hpp"
#include "core/training/training.hpp"

namespace wish::wire {

nlohmann::json training_report_json(const TrainingReport& report);
// One row of the feature-family comparison: {"family", "features", "best_C", "best_gamma", "grid_score",
// "test_accuracy", "nested_cv_mean", "nested_cv_std"}.
nlohmann::json family_score_json(const FamilyScore& score);

// What a training run adds to the report: where the data and the model are, the comparison, what was skipped.
struct TrainingRunInfo {
  std::string input, model_file, model_sha256;
  std::vector<FamilyScore> comparison;
  std::vector<MeshLoss> lost;           // refused or failed items: {"file", "label", "code", "message"}
  std::vector<std::string> unlabelled;  // descriptor rows without a label ("code": "no_label")
};
nlohmann::json training_run_json(const TrainingReport& report, const TrainingRunInfo& run);

}  // namespace wish::wire
