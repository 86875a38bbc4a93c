#include <gtest/gtest.h>

#include <filesystem>
#include <algorithm>
#include <fstream>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/classify/classifier_model.hpp"
#include "core/classify/default_recipe.hpp"
#include "core/classify/sha256.hpp"
#include "core/common/errors.hpp"
#include "core/training/descriptor_table.hpp"
#include "tests/classify/classify_test_data.hpp"
#include "tests/testing/test_data.hpp"

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

TEST(ModelFile, DescriptorRecipeSurvives) {
  auto opts = testing::quick_train_options();
  opts.nested_repeats = 0;
  opts.recipe.map.method = MapMethod::Cmcf;
  opts.recipe.map.willmore.tau = 0.5;
  opts.recipe.sh.regularization = 3e-4;
  opts.recipe.sh.weighting = FitWeighting::Uniform;
  opts.recipe.sh.solver = FitSolver::Banded;
  // Every other field away from its default too: the file must carry all of them (descriptor_recipe_codec.hpp).
  opts.recipe.map.method = MapMethod::Linear;
  opts.recipe.map.willmore.complex_dirac = false;
  opts.recipe.map.cmcf.fallback_max_steps = 77;
  opts.recipe.map.linear.always_clamp = true;
  opts.recipe.map.untangle = false;
  opts.recipe.map.solver = LinearSolverKind::EigenSimplicial;
  opts.recipe.map.verification.degenerate_height = 3e-13;
  opts.recipe.sh.gram = GramMethod::Product;
  opts.recipe.features.scale = ScaleNormalization::ByFirstInvariant;
  opts.recipe.features.l_min = 2;
  opts.recipe.off_recipe = OffRecipePolicy::AcceptFlagged;
  const auto model = train_classifier(testing::synthetic_samples(2, 8, 3), opts).model;
  const auto loaded = ClassifierModel::from_json_text(model.to_json_text());
  const auto& d = loaded.recipe();
  EXPECT_TRUE(d == opts.recipe);
  EXPECT_EQ(d.off_recipe, OffRecipePolicy::AcceptFlagged);
  EXPECT_EQ(d.features.l_min, 2);
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
    d["payload"]["recipe"]["features"]["l_max"] = 7;
    expect_refused(reseal(d), "model_invalid", "features.names");
  }
  {
    auto d = doc;
    d["payload"]["recipe"]["sh"].erase("lmax");
    expect_refused(reseal(d), "model_invalid", "recipe.sh.lmax");
  }
  {
    auto d = doc;
    d["payload"]["recipe"]["off_recipe"] = "sometimes";
    expect_refused(reseal(d), "model_invalid", "recipe.off_recipe 'sometimes'");
  }
  {
    auto d = doc;
    d["payload"]["recipe"]["recipe_version"] = 99;
    expect_refused(reseal(d), "model_version", "recipe version 99");
  }
  {
    auto d = doc;
    d["payload"]["svm"]["kernel"] = "linear";
    expect_refused(reseal(d), "model_invalid", "RBF");
  }
  EXPECT_NO_THROW((void)ClassifierModel::from_json_text(reseal(doc)));
}

// An unknown key anywhere in the file is refused (issue 27): a reader that skipped it would compute with its own
// value of a setting the file states. The message names the key's path.
TEST(ModelFile, RefusesUnknownKeysAnywhereNamingThem) {
  const auto doc = nlohmann::json::parse(trained().to_json_text());
  const std::vector<std::vector<std::string>> places{
      {},
      {"payload"},
      {"payload", "svm"},
      {"payload", "scaler"},
      {"payload", "training"},
      {"payload", "recipe"},
      {"payload", "recipe", "map"},
      {"payload", "recipe", "map", "cmcf"},
      {"payload", "recipe", "map", "area_correction"},
      {"payload", "recipe", "sh"},
      {"payload", "recipe", "features"},
      {"payload", "novelty"}};
  for (const auto& place : places) {
    auto d = doc;
    nlohmann::json* at = &d;
    std::string path = place.empty() ? "document" : "";
    for (const auto& k : place) {
      at = &(*at)[k];
      path += (path.empty() ? "" : ".") + k;
    }
    ASSERT_TRUE(at->is_object()) << path;
    (*at)["frobnication"] = 1;
    expect_refused(reseal(d), "model_version", "unknown key " + path + ".frobnication");
  }
  {
    auto d = doc;
    ASSERT_FALSE(d["payload"]["training"]["class_spectra"].empty());
    d["payload"]["training"]["class_spectra"][0]["extra"] = 1;
    expect_refused(reseal(d), "model_version", "unknown key payload.training.class_spectra[].extra");
  }
  // ... and ClassifierModel::load names the file too.
  auto d = doc;
  d["payload"]["recipe"]["map"]["frobnication"] = true;
  const auto path = std::filesystem::temp_directory_path() / "wish_model_unknown_key_test.json";
  std::ofstream(path) << reseal(d);
  try {
    (void)ClassifierModel::load(path);
    FAIL() << "a model with an unknown key was loaded";
  } catch (const InvalidInputError& e) {
    EXPECT_EQ(e.code(), "model_version");
    EXPECT_NE(std::string(e.what()).find(path.string() + ": unknown key payload.recipe.map.frobnication"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

// Version 3 (chain_budget_seconds, linear_reserve_seconds, cmcf.stall_patience) is what today's defaults write; a
// newer version is refused with the reason. A file of a computed version (3 on) holds every field of its version,
// while a version-2 file without a version-3 field takes the field's legacy value (how version-2 builds computed).
TEST(ModelFile, RecipeVersionsOldAndNew) {
  const auto doc = nlohmann::json::parse(trained().to_json_text());
  ASSERT_EQ(doc["payload"]["recipe"]["recipe_version"], 4);
  {
    auto d = doc;
    d["payload"]["recipe"]["recipe_version"] = DescriptorRecipe::kVersion + 1;
    expect_refused(reseal(d), "model_version", "written by a newer wish");
  }
  auto d = doc;
  d["payload"]["recipe"]["map"]["cmcf"].erase("stall_patience");
  expect_refused(reseal(d), "model_invalid", "missing field payload.recipe.map.cmcf.stall_patience");
  d["payload"]["recipe"]["recipe_version"] = 2;
  d["payload"]["recipe"]["map"].erase("chain_budget_seconds");
  d["payload"]["recipe"]["features"].erase("spectrum_count");
  const ClassifierModel v2 = ClassifierModel::from_json_text(reseal(d));
  EXPECT_EQ(v2.recipe().map.cmcf.stall_patience, 1);
  EXPECT_EQ(v2.recipe().map.chain_budget_seconds, 0.0);
  EXPECT_EQ(v2.recipe().features.spectrum_count, 0);
  EXPECT_EQ(v2.recipe().map.linear_reserve_seconds, trained().recipe().map.linear_reserve_seconds);  // as stated
  // Written again, its version is computed from its fields: linear_reserve_seconds is a version-3 field away from
  // its legacy value 0.
  EXPECT_EQ(nlohmann::json::parse(v2.to_json_text())["payload"]["recipe"]["recipe_version"], 3);
}

// map.min_fallback_flow_seconds was in version-2 files for a few hours of 2026-12-02: at 0 (what this build
// computes) such a file loads, another value is refused, and in a version-3 file it is an unknown key.
TEST(ModelFile, RetiredKeyOnlyInTheVersionsThatHadIt) {
  auto d = nlohmann::json::parse(trained().to_json_text());
  d["payload"]["recipe"]["map"]["min_fallback_flow_seconds"] = 0.0;
  expect_refused(reseal(d), "model_version", "unknown key payload.recipe.map.min_fallback_flow_seconds");
  d["payload"]["recipe"]["recipe_version"] = 2;
  EXPECT_NO_THROW((void)ClassifierModel::from_json_text(reseal(d)));
  d["payload"]["recipe"]["map"]["min_fallback_flow_seconds"] = 0.5;
  expect_refused(reseal(d), "model_version", "retired");
}

// The bundled model is exactly what this build writes for it (its recipe version computed from its fields), and its
// recipe is `wish train`'s default (scripts/make-default-model.sh restates none of it; default_recipe.hpp).
TEST(ModelFile, BundledDefaultModelIsAsThisBuildWritesIt) {
  const auto path = testing::project_data_dir() / "models" / "default.json";
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  const ClassifierModel model = ClassifierModel::load(path);
  EXPECT_EQ(model.to_json_text(), text.str());
  EXPECT_EQ(recipe_version_of(model.recipe()), recipe_version_of(default_training_recipe()));
  EXPECT_TRUE(model.recipe() == default_training_recipe());
}

// The novelty block (issue 25; per class since format 4, whitened since 5): written with the version that introduced
// it, so an older reader refuses the file; optional on read (a file without it loads and predicts without a novelty
// figure); a block in a file that claims an older version is refused; an inconsistent block is refused with its path.
TEST(ModelFile, NoveltyBlockIsVersion5OptionalAndChecked) {
  const auto doc = nlohmann::json::parse(trained().to_json_text());
  ASSERT_TRUE(trained().has_novelty());
  EXPECT_EQ(doc["format_version"], 5);
  ASSERT_TRUE(doc["payload"].contains("novelty"));
  ASSERT_TRUE(doc["payload"]["novelty"].contains("reference_classes"));
  ASSERT_TRUE(doc["payload"]["novelty"].contains("whitening"));
  const auto sample = testing::synthetic_samples(3, 1, 5).front().features;
  {
    const ClassifierModel loaded = ClassifierModel::from_json_text(doc.dump());
    const Prediction a = trained().predict(sample), b = loaded.predict(sample);
    ASSERT_TRUE(a.novelty && b.novelty);
    EXPECT_EQ(a.novelty->score, b.novelty->score);
    EXPECT_EQ(a.novelty->p_value, b.novelty->p_value);
    EXPECT_EQ(a.novelty->threshold, b.novelty->threshold);
  }
  {
    auto d = doc;
    d["payload"].erase("novelty");
    const ClassifierModel without = ClassifierModel::from_json_text(reseal(d));
    EXPECT_FALSE(without.has_novelty());
    const Prediction p = without.predict(sample);
    EXPECT_FALSE(p.novelty.has_value());
    EXPECT_EQ(p.label, trained().predict(sample).label);
    EXPECT_EQ(nlohmann::json::parse(without.to_json_text())["format_version"], 2);
  }
  {
    auto d = doc;
    d["format_version"] = 2;
    expect_refused(reseal(d), "model_invalid", "needs format_version 3");
  }
  {
    // A format-3 reader knows no reference_classes: the per-class block in a file that says 3 is refused by it.
    auto d = doc;
    d["format_version"] = 3;
    expect_refused(reseal(d), "model_version", "payload.novelty.reference_classes");
  }
  {
    // A format-4 reader knows no whitening: the whitened block in a file that says 4 is refused by it.
    auto d = doc;
    d["format_version"] = 4;
    expect_refused(reseal(d), "model_version", "payload.novelty.whitening");
  }
  {
    auto d = doc;
    d["payload"]["novelty"]["whitening"][0].erase(0);
    expect_refused(reseal(d), "model_invalid", "novelty.whitening");
  }
  {
    auto d = doc;
    d["payload"]["novelty"]["whitening"].erase(0);
    expect_refused(reseal(d), "model_invalid", "novelty.whitening");
  }
  {
    auto d = doc;
    d["payload"]["novelty"]["whitening"][0][1] = d["payload"]["novelty"]["whitening"][0][1].get<double>() + 1;
    expect_refused(reseal(d), "model_invalid", "not symmetric");
  }
  {
    auto d = doc;
    d["payload"]["novelty"]["reference_classes"][0] = 7;
    expect_refused(reseal(d), "model_invalid", "reference class 7");
  }
  {
    auto d = doc;
    d["payload"]["novelty"]["loo_scores"][0].erase(0);
    expect_refused(reseal(d), "model_invalid", "leave-one-out scores");
  }
  {
    auto d = doc;
    d["payload"]["novelty"]["reference"][0].erase(0);
    expect_refused(reseal(d), "model_invalid", "novelty.reference");
  }
  {
    auto d = doc;
    d["payload"]["novelty"]["quantile"] = 1.5;
    expect_refused(reseal(d), "model_invalid", "quantile");
  }
}

// Cross-validated calibration scores (the --novelty-folds option): written as format 6 with calibration_folds, read
// back to the same figure; a format-5 reader knows no calibration_folds and refuses the block by it; bad fold counts
// are refused. Without the option the file stays format 5 (above).
TEST(ModelFile, CrossValidatedNoveltyIsVersion6AndChecked) {
  auto opts = testing::quick_train_options();
  opts.nested_repeats = 0;
  opts.novelty_folds = 10;
  const ClassifierModel model = train_classifier(testing::synthetic_samples(3, 12, 11), opts).model;
  ASSERT_EQ(model.novelty_calibration()->calibration_folds, 10);
  const auto doc = nlohmann::json::parse(model.to_json_text());
  EXPECT_EQ(doc["format_version"], 6);
  EXPECT_EQ(doc["payload"]["novelty"]["calibration_folds"], 10);
  const auto sample = testing::synthetic_samples(3, 1, 5).front().features;
  const ClassifierModel loaded = ClassifierModel::from_json_text(doc.dump());
  EXPECT_EQ(loaded.novelty_calibration()->calibration_folds, 10);
  EXPECT_EQ(loaded.novelty_calibration()->loo_scores, model.novelty_calibration()->loo_scores);
  EXPECT_EQ(loaded.predict(sample).novelty->score, model.predict(sample).novelty->score);
  EXPECT_EQ(loaded.to_json_text(), model.to_json_text());
  // Same samples, same score at prediction; other calibration scores than leave-one-out.
  EXPECT_EQ(trained().predict(sample).novelty->score, model.predict(sample).novelty->score);
  EXPECT_NE(trained().novelty_calibration()->loo_scores, model.novelty_calibration()->loo_scores);
  {
    auto d = doc;
    d["format_version"] = 5;
    expect_refused(reseal(d), "model_version", "payload.novelty.calibration_folds");
  }
  for (const int folds : {1, -3, 10000}) {
    auto d = doc;
    d["payload"]["novelty"]["calibration_folds"] = folds;
    expect_refused(reseal(d), "model_invalid", "calibration_folds");
  }
  {
    auto d = doc;
    d["payload"]["novelty"].erase("calibration_folds");
    expect_refused(reseal(d), "model_invalid", "calibration_folds");
  }
}

std::filesystem::path fixture_dir() { return testing::project_data_dir().parent_path() / "tests" / "classify" / "data"; }

// A model file of format version 3 (main df31c18's `wish train` on half the demo descriptors without the neurons,
// committed as a fixture) keeps its one-set novelty figure: it loads and computes the scores, p-values, flags and
// labels that build computed (tests/classify/data/model_format_v3_predictions.csv, columns *_v3), and is saved
// again as format 3.
TEST(ModelFileMigration, FormatVersion3KeepsItsOneSetNoveltyFigure) {
  const auto path = fixture_dir() / "model_format_v3.json";
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  const ClassifierModel model = ClassifierModel::load(path);
  ASSERT_TRUE(model.has_novelty());
  EXPECT_FALSE(model.novelty_calibration()->per_class);
  std::ifstream csv_in(fixture_dir() / "model_format_v3_predictions.csv");
  std::stringstream text;
  text << csv_in.rdbuf();
  const auto rows = parse_csv(text.str());
  const auto table = read_descriptor_table(text.str());
  ASSERT_EQ(table.samples.size(), 15u);
  auto column = [&](const std::string& name) {
    const auto c = std::find(rows[0].begin(), rows[0].end(), name) - rows[0].begin();
    EXPECT_LT(c, static_cast<long>(rows[0].size())) << name;
    return static_cast<std::size_t>(c);
  };
  const std::size_t label = column("predicted_v3"), novel = column("novel_v3"), score = column("novelty_score_v3"),
                    p_value = column("novelty_p_value_v3");
  int flagged = 0;
  for (std::size_t i = 0; i < table.samples.size(); ++i) {
    const auto& row = rows[i + 1];
    const Prediction p = model.predict(table.samples[i].features);
    ASSERT_TRUE(p.novelty);
    EXPECT_EQ(p.label, row[label]) << table.samples[i].id;
    EXPECT_EQ(p.novelty->novel, row[novel] == "true") << table.samples[i].id;
    EXPECT_NEAR(p.novelty->score, std::stod(row[score]), 1e-8 * std::stod(row[score])) << table.samples[i].id;
    EXPECT_DOUBLE_EQ(p.novelty->p_value, std::stod(row[p_value])) << table.samples[i].id;
    flagged += p.novelty->novel;
  }
  EXPECT_EQ(flagged, 4);  // four of the five neurons, none of the known classes' members (as written)
  EXPECT_EQ(nlohmann::json::parse(model.to_json_text())["format_version"], 3);
}

// Checks that `model` computes, for every row of tests/classify/data/demo_descriptors_fixture.csv (the bundled
// data/models/demo-descriptors.csv as main ddc85ad shipped it, frozen: the bundled table moves with the default
// recipe), the label, novelty flag, score and p-value that the build which wrote the fixture printed
// (`wish predict --csv`, tests/classify/data/<predictions>).
void expect_fixture_predictions(const ClassifierModel& model, const std::string& predictions) {
  std::ifstream expected_in(fixture_dir() / predictions);
  std::stringstream expected_text;
  expected_text << expected_in.rdbuf();
  const auto expected = parse_csv(expected_text.str());
  std::ifstream csv_in(fixture_dir() / "demo_descriptors_fixture.csv");
  std::stringstream text;
  text << csv_in.rdbuf();
  const auto table = read_descriptor_table(text.str());
  ASSERT_EQ(expected.size(), table.samples.size() + 1);
  auto column = [&](const std::string& name) {
    const auto c = std::find(expected[0].begin(), expected[0].end(), name) - expected[0].begin();
    EXPECT_LT(c, static_cast<long>(expected[0].size())) << name;
    return static_cast<std::size_t>(c);
  };
  const std::size_t label = column("label"), novel = column("novel"), score = column("novelty_score"),
                    p_value = column("novelty_p_value");
  for (std::size_t i = 0; i < table.samples.size(); ++i) {
    const auto& row = expected[i + 1];
    const Prediction p = model.predict(table.samples[i].features);
    ASSERT_TRUE(p.novelty);
    EXPECT_EQ(p.label, row[label]) << table.samples[i].id;
    EXPECT_EQ(p.novelty->novel, row[novel] == "true") << table.samples[i].id;
    EXPECT_NEAR(p.novelty->score, std::stod(row[score]), 1e-8 * std::stod(row[score])) << table.samples[i].id;
    EXPECT_NEAR(p.novelty->p_value, std::stod(row[p_value]), 1e-9) << table.samples[i].id;
  }
}

// A model file of format version 4 (the bundled default model as main 41c0f1d shipped it, committed as a fixture)
// keeps its Euclidean per-class novelty figure: it loads and computes the scores, p-values, flags and labels that
// build's `wish predict --descriptors data/models/demo-descriptors.csv --csv` wrote
// (tests/classify/data/model_format_v4_predictions.csv), and is saved again as format 4.
TEST(ModelFileMigration, FormatVersion4KeepsItsEuclideanNoveltyFigure) {
  const ClassifierModel model = ClassifierModel::load(fixture_dir() / "model_format_v4.json");
  ASSERT_TRUE(model.has_novelty());
  EXPECT_TRUE(model.novelty_calibration()->per_class);
  EXPECT_EQ(model.novelty_calibration()->whitening.size(), 0);
  expect_fixture_predictions(model, "model_format_v4_predictions.csv");
  EXPECT_EQ(nlohmann::json::parse(model.to_json_text())["format_version"], 4);
}

// A model file of format version 5 (the default model as scripts/make-default-model.sh made it with the build of
// main 0041f96, committed as a fixture; leave-one-out scores, whitened) loads and computes the labels, scores,
// p-values and flags that build printed (`wish predict --csv` on data/models/demo-descriptors.csv), and is saved
// again as format 5, byte for byte.
TEST(ModelFileMigration, FormatVersion5KeepsItsFigure) {
  const auto path = fixture_dir() / "model_format_v5.json";
  const ClassifierModel model = ClassifierModel::load(path);
  ASSERT_TRUE(model.has_novelty());
  EXPECT_EQ(model.novelty_calibration()->calibration_folds, 0);
  EXPECT_NE(model.novelty_calibration()->whitening.size(), 0);
  expect_fixture_predictions(model, "model_format_v5_predictions.csv");
  std::ifstream in(path, std::ios::binary);
  std::stringstream file_text;
  file_text << in.rdbuf();
  EXPECT_EQ(model.to_json_text(), file_text.str());
}

// A model file of format version 1 (the bundled default model as main cfdc7a1 wrote it, committed as a fixture)
// loads through the migration and predicts what version-1 code predicted: the labels of its training report's
// hold-out split (tests/classify/data/model_format_v1_predictions.csv, column predicted_v1).

TEST(ModelFileMigration, FormatVersion1LoadsAndPredictsTheSame) {
  const auto v1_path = fixture_dir() / "model_format_v1.json";
  ASSERT_TRUE(std::filesystem::exists(v1_path)) << v1_path;
  std::ifstream in(v1_path);
  const auto v1_doc = nlohmann::json::parse(in);
  ASSERT_EQ(v1_doc["format_version"], 1);
  const ClassifierModel model = ClassifierModel::load(v1_path);
  const DescriptorRecipe& r = model.recipe();
  EXPECT_EQ(r.off_recipe, OffRecipePolicy::AcceptFlagged);  // what version-1 code did with fallback maps
  EXPECT_EQ(r.map.method, MapMethod::Willmore);
  EXPECT_EQ(r.map.area_correction.method, AreaCorrection::None);  // recipe version 2 field: the conformal map
  EXPECT_EQ(r.sh.lmax, 5);
  EXPECT_EQ(r.sh.regularization, 1e-5);
  EXPECT_EQ(r.features.l_max, 5);
  EXPECT_TRUE(r.features.log_transform);
  EXPECT_EQ(r.features.family, FeatureFamily::Invariants);
  EXPECT_EQ(model.classes().size(), 6u);

  std::ifstream csv_in(fixture_dir() / "model_format_v1_predictions.csv");
  std::stringstream text;
  text << csv_in.rdbuf();
  const auto rows = parse_csv(text.str());
  const auto table = read_descriptor_table(text.str());
  ASSERT_EQ(rows.size(), table.samples.size() + 1);
  ASSERT_EQ(table.samples.size(), 15u);
  const auto column = std::find(rows[0].begin(), rows[0].end(), "predicted_v1") - rows[0].begin();
  ASSERT_LT(column, static_cast<long>(rows[0].size()));

  // Saved again it is a version-2 file that predicts bit for bit the same as the migrated one.
  const std::string v2_text = model.to_json_text();
  // Version 2, not 3: it has no novelty calibration (format 3's block), so readers of version 2 still read it.
  EXPECT_EQ(nlohmann::json::parse(v2_text)["format_version"], 2);
  EXPECT_FALSE(model.has_novelty());
  const ClassifierModel reloaded = ClassifierModel::from_json_text(v2_text);
  EXPECT_TRUE(reloaded.recipe() == model.recipe());
  for (std::size_t i = 0; i < table.samples.size(); ++i) {
    const Prediction p = model.predict(table.samples[i].features);
    EXPECT_EQ(p.label, rows[i + 1][static_cast<std::size_t>(column)]) << table.samples[i].id;
    const Prediction q = reloaded.predict(table.samples[i].features);
    EXPECT_EQ(q.label, p.label);
    EXPECT_EQ(q.probabilities, p.probabilities);
    EXPECT_EQ(q.margin, p.margin);
  }
}

TEST(ModelFileMigration, Version1WithBrokenContentIsStillRefused) {
  std::ifstream in(fixture_dir() / "model_format_v1.json");
  auto doc = nlohmann::json::parse(in);
  doc["payload"]["features"]["l_max"] = 9;  // beyond descriptor.sh.lmax 5, and names no longer match
  expect_refused(reseal(doc), "model_invalid", "features.names");
  doc = nlohmann::json::parse(std::ifstream(fixture_dir() / "model_format_v1.json"));
  doc["payload"].erase("descriptor");
  expect_refused(reseal(doc), "model_invalid", "payload.descriptor");
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

namespace wish {
namespace {

// A small 3-class model whose novelty block uses `rule` (the format tests of issue 38's rules).
ClassifierModel trained_with_novelty_rule(NoveltyRule rule) {
  auto opts = testing::quick_train_options();
  opts.nested_repeats = 0;
  opts.novelty_rule = rule;
  return train_classifier(testing::synthetic_samples(3, 12, 11), opts).model;
}

// Issue 38: the predicted-class rule is format 7 (payload.novelty.rule), a format-6 reader refuses it by its key,
// and a prediction says why: one ratio per class, the reported class's ratio is score / threshold.
TEST(ModelFile, PredictedClassNoveltyRuleIsVersion7AndSaysWhy) {
  const ClassifierModel model = trained_with_novelty_rule(NoveltyRule::PredictedClass);
  const auto doc = nlohmann::json::parse(model.to_json_text());
  EXPECT_EQ(doc["format_version"], 7);
  EXPECT_EQ(doc["payload"]["novelty"]["rule"], "predicted_class");
  const ClassifierModel loaded = ClassifierModel::from_json_text(doc.dump());
  EXPECT_EQ(loaded.novelty_calibration()->rule, NoveltyRule::PredictedClass);
  EXPECT_EQ(loaded.to_json_text(), model.to_json_text());
  for (const auto& s : testing::synthetic_samples(3, 4, 5)) {
    const Prediction p = loaded.predict(s.features);
    ASSERT_TRUE(p.novelty);
    ASSERT_EQ(p.novelty->class_ratios.size(), 3u);
    // The reported class is the predicted one, and its ratio is its score over its threshold.
    EXPECT_EQ(model.classes()[static_cast<std::size_t>(p.novelty->group)], p.label);
    EXPECT_NEAR(p.novelty->class_ratios[static_cast<std::size_t>(p.novelty->group)], p.novelty->score / p.novelty->threshold, 1e-12);
    EXPECT_EQ(p.novelty->novel, p.novelty->score > p.novelty->threshold);
    // The nearest-class rule on the same calibration reports the smallest ratio.
    const Prediction q = trained().predict(s.features);
    const auto& r = q.novelty->class_ratios;
    EXPECT_EQ(r[static_cast<std::size_t>(q.novelty->group)], *std::min_element(r.begin(), r.end()));
  }
  {
    auto d = doc;
    d["format_version"] = 6;
    expect_refused(reseal(d), "model_version", "payload.novelty.rule");
  }
  {
    auto d = doc;
    d["payload"]["novelty"]["rule"] = "loudest_class";
    expect_refused(reseal(d), "model_invalid", "novelty.rule");
  }
}

}  // namespace
}  // namespace wish

namespace wish {
namespace {

// Issue 38, second pass: the median_scale rule is format 8; a format-7 reader refuses it by number.
TEST(ModelFile, MedianScaleNoveltyRuleIsVersion8) {
  const ClassifierModel model = trained_with_novelty_rule(NoveltyRule::MedianScale);
  const auto doc = nlohmann::json::parse(model.to_json_text());
  EXPECT_EQ(doc["format_version"], 8);
  EXPECT_EQ(doc["payload"]["novelty"]["rule"], "median_scale");
  const ClassifierModel loaded = ClassifierModel::from_json_text(doc.dump());
  EXPECT_EQ(loaded.novelty_calibration()->rule, NoveltyRule::MedianScale);
  EXPECT_EQ(loaded.to_json_text(), model.to_json_text());
  for (const auto& s : testing::synthetic_samples(3, 4, 5)) {
    const Prediction p = loaded.predict(s.features);
    ASSERT_TRUE(p.novelty);
    EXPECT_EQ(p.novelty->novel, p.novelty->score > p.novelty->threshold);
  }
  auto d = doc;
  d["format_version"] = 7;
  expect_refused(reseal(d), "model_version", "median_scale");
}

}  // namespace
}  // namespace wish
