#pragma once
// Internal: what a ClassifierModel consists of. Built by training (core/training/training.cpp) or by loading a model
// file (model_file.cpp); immutable afterwards and shared between copies.

#include <optional>
#include <string>
#include <vector>

#include "core/classify/classifier_model.hpp"
#include "core/classify/standard_scaler.hpp"
#include "core/classify/svm_engine.hpp"

namespace wish {

struct ClassifierModel::State {
  std::string name = "wish-svm";
  std::string version = "1";
  std::vector<std::string> classes;  // class label i of the SVM is classes[i]; sorted
  DescriptorRecipe recipe;
  StandardScaler scaler;
  SvmEngine svm;
  TrainingSummary summary;
  std::optional<NoveltyCalibration> novelty;  // payload.novelty; absent in files written before issue 25
  std::string payload_sha256;        // filled by make_state()

  State(SvmEngine engine) : svm(std::move(engine)) {}
};

// Validates the parts against each other (sizes, names) and seals the payload hash; throws
// InvalidInputError("model_invalid") on inconsistency.
std::shared_ptr<const ClassifierModel::State> finalize_state(std::shared_ptr<ClassifierModel::State> state);

}  // namespace wish
