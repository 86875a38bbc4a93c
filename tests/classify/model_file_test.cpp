#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/classify/classifier_model.hpp"
#include "core/classify/sha256.hpp"
#include "core/common/errors.hpp"
#include "tests/classify/classify_test_data.hpp"

namespace wish {
namespace {

const ClassifierModel& trained() {
  static const ClassifierModel model = [] {
    auto opts = testing::quick_train_options();
    opts.nested_repeats = 0;
    return train_classifier(testing::synthetic_samples(3, 12, 11), opts).model;
  }();
  return model;
}

void expect_refused(const std::string& text, const std::string& code, const std::string& message_part) {
  try {
    (void)ClassifierModel::from_json_text(text);
    FAIL() << "accepted a bad model (expected " << code << ")";
  } catch (const InvalidInputError& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_NE(std::string(e.what()).find(message_part), std::string::npos) << e.what();
  }
}

// Re-seals an edited payload, as a deliberate converter would: then the consistency checks must catch it.
std::string reseal(nlohmann::json doc) {
  doc["payload_sha256"] = Sha256::hex(doc["payload"].dump());
  return doc.dump();
}

TEST(ModelFile, RoundTripGivesIdenticalPredictions) {
  const ClassifierModel& model = trained();
  const auto path = std::filesystem::temp_directory_path() / "wish_model_roundtrip_test.json";
  model.save(path);
  const ClassifierModel loaded = ClassifierModel::load(path);
  std::filesystem::remove(path);
  EXPECT_EQ(loaded.to_json_text(), model.to_json_text());
  EXPECT_EQ(loaded.classes(), model.classes());
  EXPECT_EQ(loaded.feature_spec(), model.feature_spec());
  EXPECT_EQ(loaded.payload_sha256(), model.payload_sha256());
  EXPECT_EQ(loaded.training_summary().trained_at, "2024-01-01T00:00:00Z");
  for (const auto& s : testing::synthetic_samples(3, 10, 99)) {
    const Prediction a = model.predict(s.features), b = loaded.predict(s.features);
    EXPECT_EQ(a.label, b.label);
    EXPECT_EQ(a.margin, b.margin);
    EXPECT_EQ(a.probabilities, b.probabilities);
  }
}

TEST(ModelFile, DescriptorSettingsSurvive) {
  auto opts = testing::quick_train_options();
  opts.nested_repeats = 0;
  opts.descriptor.map.method = MapMethod::Cmcf;
  opts.descriptor.map.willmore.tau = 0.5;
  opts.descriptor.sh.regularization = 3e-4;
  opts.descriptor.sh.weighting = FitWeighting::Uniform;
  opts.descriptor.sh.solver = FitSolver::Banded;
  // Every other field away from its default too: the file must carry all of them (descriptor_settings_codec.hpp).
  opts.descriptor.map.method = MapMethod::Linear;
  opts.descriptor.map.willmore.complex_dirac = false;
  opts.descriptor.map.cmcf.fallback_max_steps = 77;
  opts.descriptor.map.linear.always_clamp = true;
  opts.descriptor.map.untangle = false;
  opts.descriptor.map.solver = LinearSolverKind::EigenSimplicial;
  opts.descriptor.map.verification.degenerate_height = 3e-13;
  opts.descriptor.sh.gram = GramMethod::Product;
  const auto model = train_classifier(testing::synthetic_samples(2, 8, 3), opts).model;
  const auto loaded = ClassifierModel::from_json_text(model.to_json_text());
  const auto& d = loaded.descriptor_settings();
  EXPECT_TRUE(d == opts.descriptor);
  EXPECT_EQ(d.map.method, MapMethod::Linear);
  EXPECT_EQ(d.map.willmore.tau, 0.5);
  EXPECT_EQ(d.sh.regularization, 3e-4);
  EXPECT_EQ(d.sh.weighting, FitWeighting::Uniform);
  EXPECT_EQ(d.sh.solver, FitSolver::Banded);
  EXPECT_EQ(d.sh.lmax, 8);
}

TEST(ModelFile, RefusesTruncatedFile) {
  const std::string text = trained().to_json_text();
  expect_refused(text.substr(0, text.size() / 2), "model_invalid", "truncated");
  expect_refused("", "model_invalid", "JSON");
}

TEST(ModelFile, RefusesEditedFile) {
  std::string text = trained().to_json_text();
  const auto pos = text.find("\"C\":");
  ASSERT_NE(pos, std::string::npos);
  text.insert(pos + 5, "1");  // C = 1x... : still valid JSON, different content
  expect_refused(text, "model_invalid", "edited or corrupted");
}

TEST(ModelFile, RefusesWrongVersionAndFormat) {
  auto doc = nlohmann::json::parse(trained().to_json_text());
  doc["format_version"] = 99;
  expect_refused(doc.dump(), "model_version", "version 99");
  doc["format_version"] = 1;
  doc["format"] = "something-else";
  expect_refused(doc.dump(), "model_invalid", "not a WISH classifier");
}

TEST(ModelFile, RefusesMismatchedSizesEvenWhenResealed) {
  const auto doc = nlohmann::json::parse(trained().to_json_text());
  {
    auto d = doc;
    d["payload"]["scaler"]["mean"].erase(0);
    expect_refused(reseal(d), "model_invalid", "scaler");
  }
  {
    auto d = doc;
    d["payload"]["classes"].push_back("extra");
    expect_refused(reseal(d), "model_invalid", "class names");
  }
  {
    auto d = doc;
    d["payload"]["svm"]["rho"].erase(0);
    expect_refused(reseal(d), "model_invalid", "rho");
  }
  {
    auto d = doc;
    d["payload"]["svm"]["support_vectors"][0].erase(0);
    expect_refused(reseal(d), "model_invalid", "support_vectors");
  }
  {
    auto d = doc;
    d["payload"]["features"]["l_max"] = 7;
    expect_refused(reseal(d), "model_invalid", "features.names");
  }
  {
    auto d = doc;
    d["payload"]["descriptor"]["sh"].erase("lmax");
    expect_refused(reseal(d), "model_invalid", "descriptor.sh.lmax");
  }
  {
    auto d = doc;
    d["payload"]["svm"]["kernel"] = "linear";
    expect_refused(reseal(d), "model_invalid", "RBF");
  }
  EXPECT_NO_THROW((void)ClassifierModel::from_json_text(reseal(doc)));
}

TEST(ModelFile, LoadNamesThePath) {
  const auto path = std::filesystem::temp_directory_path() / "wish_model_bad_test.json";
  std::ofstream(path) << "{";
  try {
    (void)ClassifierModel::load(path);
    FAIL();
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos);
  }
  std::filesystem::remove(path);
  EXPECT_THROW((void)ClassifierModel::load(path), InvalidInputError);
}

TEST(ClassifierModel, PredictionRefusesMissingFeatures) {
  ShapeFeatures f;
  f.invariants = Eigen::VectorXd::Ones(3);  // model needs xi(6)
  try {
    (void)trained().predict(f);
    FAIL();
  } catch (const InvalidInputError& e) {
    EXPECT_EQ(e.code(), "feature_mismatch");
  }
}

}  // namespace
}  // namespace wish
