// The prediction's JSON (wire/wire_json.hpp prediction_json): "novel" beside the label and probabilities, with the
// novelty figures, or null and the reason when the model has none (a model file written before format 3).
#include <gtest/gtest.h>

#include "core/classify/classifier_model.hpp"
#include "wire/wire_json.hpp"

namespace wish {
namespace {

Prediction base() {
  Prediction p;
  p.label = "neuron";
  p.probabilities = {{"astrocyte", 0.2}, {"neuron", 0.8}};
  p.margin = 0.5;
  return p;
}

TEST(PredictionJson, NovelBesideTheLabelWithItsFigures) {
  Prediction p = base();
  NoveltyAssessment novel;
  novel.score = 3.5;
  novel.p_value = 0.01;
  novel.threshold = 2.0;
  novel.quantile = 0.99;
  novel.novel = true;
  p.novelty = novel;
  const nlohmann::json j = wire::prediction_json(p, "m", "1");
  EXPECT_EQ(j["label"], "neuron");  // the label stays
  EXPECT_EQ(j["novel"], true);
  EXPECT_EQ(j["novelty"]["computed"], true);
  EXPECT_EQ(j["novelty"]["score"], 3.5);
  EXPECT_EQ(j["novelty"]["p_value"], 0.01);
  EXPECT_EQ(j["novelty"]["threshold"], 2.0);
  EXPECT_EQ(j["novelty"]["quantile"], 0.99);
  p.novelty->novel = false;
  EXPECT_EQ(wire::prediction_json(p, "m", "1")["novel"], false);
}

TEST(PredictionJson, NullAndAReasonWithoutCalibration) {
  const nlohmann::json j = wire::prediction_json(base(), "m", "1");
  EXPECT_TRUE(j["novel"].is_null());
  EXPECT_EQ(j["novelty"]["computed"], false);
  EXPECT_NE(j["novelty"]["reason"].get<std::string>().find("no novelty calibration"), std::string::npos);
}

}  // namespace
}  // namespace wish
