// The training report's JSON (wire/training_report_json.hpp) carries exactly the report's figures: the grid, the
// confusion matrix, per-class scores and losses, and what a training run adds (input, comparison, skipped items).
#include <gtest/gtest.h>

#include <cmath>

#include "core/training/dataset.hpp"
#include "core/training/training.hpp"
#include "tests/classify/classify_test_data.hpp"
#include "wire/training_report_json.hpp"

namespace wish {
namespace {

TEST(TrainingReportJson, CarriesTheReportsFigures) {
  const auto samples = testing::synthetic_samples(3, 20, 22);
  auto opts = testing::quick_train_options(6);
  opts.losses = {{"lost.ply", "class_b", "map_failed", "flipped faces"}};
  const auto trained = train_classifier(samples, opts);
  const TrainingReport& rep = trained.report;
  const nlohmann::json j = wire::training_report_json(rep);

  ASSERT_EQ(j.at("classes").size(), 3u);
  EXPECT_EQ(j["classes"][1]["label"], "class_b");
  EXPECT_EQ(j["classes"][1]["count"], rep.class_counts[1]);
  // grid: rows C, columns gamma, the mean accuracy of every cell
  ASSERT_EQ(j["grid"]["mean_accuracy"].size(), rep.grid.Cs.size());
  ASSERT_EQ(j["grid"]["mean_accuracy"][0].size(), rep.grid.gammas.size());
  // (as written to disk: a cell skipped by early stop is null there)
  const nlohmann::json written = nlohmann::json::parse(j.dump());
  int skipped = 0, capped = 0, offset = 0;
  for (std::size_t i = 0; i < rep.grid.Cs.size(); ++i)
    for (std::size_t k = 0; k < rep.grid.gammas.size(); ++k) {
      const double v = rep.grid.mean_score(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k));
      if (std::isnan(v)) {
        EXPECT_TRUE(written["grid"]["mean_accuracy"][i][k].is_null());
        ++skipped;
      } else {
        EXPECT_DOUBLE_EQ(written["grid"]["mean_accuracy"][i][k].get<double>(), v);
      }
      EXPECT_EQ(written["grid"]["capped_fits"][i][k].get<int>(),
                rep.grid.capped_fits(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)));
      capped += rep.grid.capped_fits(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k));
      const int narrow = written["grid"]["narrow_fits"][i][k].get<int>();  // fits decided by the SVM's offset
      EXPECT_EQ(narrow, rep.grid.narrow_fits(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)));
      if (!std::isnan(v) && 2 * narrow > opts.grid_splits) ++offset;
    }
  EXPECT_EQ(written["grid"]["cells_offset_decided"].get<int>(), offset);
  EXPECT_EQ(written["grid"]["best_offset_decided"].get<bool>(), rep.grid.best_offset_decided);
  EXPECT_EQ(written["train_classes_never_predicted"].get<std::vector<std::string>>(), rep.train_classes_never_predicted);
  EXPECT_EQ(written["grid"]["cells_skipped"].get<int>(), skipped);
  EXPECT_EQ(written["grid"]["capped_fits_total"].get<int>(), capped);
  EXPECT_EQ(written["grid"]["fits"].get<int>(),
            (static_cast<int>(rep.grid.Cs.size() * rep.grid.gammas.size()) - skipped) * opts.grid_splits);
  EXPECT_TRUE(written["grid"]["early_stop"]["enabled"].get<bool>());
  EXPECT_DOUBLE_EQ(j["grid"]["best_C"].get<double>(), rep.grid.C());
  // confusion matrix: rows true class, columns predicted; sums to the held-out count
  const auto& cm = j["test"]["confusion_matrix"];
  ASSERT_EQ(cm.size(), 3u);
  int total = 0;
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(cm[i][k].get<int>(), rep.test.confusion(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)));
      total += cm[i][k].get<int>();
    }
  EXPECT_EQ(total, static_cast<int>(rep.test_indices.size()));
  EXPECT_EQ(j["test"]["predictions"].size(), rep.test_indices.size());
  ASSERT_EQ(j["test"]["per_class"].size(), rep.test.per_class.size());
  EXPECT_DOUBLE_EQ(j["test"]["per_class"][0]["f1"].get<double>(), rep.test.per_class[0].f1);
  EXPECT_EQ(j["nested_cv"]["scores"].get<std::vector<double>>(), rep.nested.scores);
  EXPECT_EQ(j["nested_cv"]["repeats"], rep.nested.repeats);
  EXPECT_EQ(j["nested_cv"]["outer_folds"], rep.nested.outer_folds);
  ASSERT_TRUE(rep.nested.interval95.has_value());
  EXPECT_DOUBLE_EQ(j["nested_cv"]["interval95"][0].get<double>(), rep.nested.interval95->low);
  EXPECT_DOUBLE_EQ(j["nested_cv"]["interval95"][1].get<double>(), rep.nested.interval95->high);
  EXPECT_EQ(j["grid"]["method"], "grid");
  EXPECT_EQ(j["grid"]["reason"], rep.search_reason);
  EXPECT_EQ(j["grid"]["search_rows"], static_cast<int>(rep.train_indices.size()));
  EXPECT_FALSE(j["grid"].contains("rungs"));
  // losses per class, by code
  bool found = false;
  for (const auto& c : j["losses"])
    if (c["label"] == "class_b") {
      EXPECT_EQ(c["lost"], 1);
      EXPECT_EQ(c["lost_by_code"]["map_failed"], 1);
      found = true;
    }
  EXPECT_TRUE(found) << j["losses"].dump();
}

TEST(TrainingReportJson, CarriesTheHalvingSchedule) {
  const auto samples = testing::synthetic_samples(3, 30, 25);
  auto opts = testing::quick_train_options(6);
  opts.scale.search = SearchMethod::Halving;
  opts.scale.halving.min_rows = 24;
  opts.nested_repeats = 0;
  const TrainingReport rep = train_classifier(samples, opts).report;
  const nlohmann::json j = wire::training_report_json(rep);
  EXPECT_EQ(j["grid"]["method"], "halving");
  ASSERT_EQ(j["grid"]["rungs"].size(), rep.grid.rungs.size());
  ASSERT_GE(rep.grid.rungs.size(), 2u);
  int fits = 0;
  for (std::size_t r = 0; r < rep.grid.rungs.size(); ++r) {
    EXPECT_EQ(j["grid"]["rungs"][r]["rows"], rep.grid.rungs[r].rows);
    EXPECT_EQ(j["grid"]["rungs"][r]["candidates"], rep.grid.rungs[r].candidates);
    fits += j["grid"]["rungs"][r]["fits"].get<int>();
  }
  EXPECT_EQ(fits, j["grid"]["fits"].get<int>());
  EXPECT_EQ(j["grid"]["cell_rung"][rep.grid.best_c][rep.grid.best_gamma].get<int>(),
            static_cast<int>(rep.grid.rungs.size()) - 1);
  EXPECT_EQ(j["grid"]["search_rows"], rep.grid.rungs.back().rows);
  EXPECT_TRUE(j["nested_cv"]["interval95"].is_null());
}

TEST(TrainingReportJson, ARunAddsInputComparisonAndSkippedItems) {
  const auto samples = testing::synthetic_samples(2, 12, 31);
  auto opts = testing::quick_train_options();
  opts.nested_repeats = 0;
  const auto trained = train_classifier(samples, opts);
  const FamilyScore score = family_score("invariants", trained.report);
  const nlohmann::json j = wire::training_run_json(
      trained.report, {"data/train", "out/model.json", "abc123", {score}, {{"x.ply", "class_a", "timeout", "late"}},
                       {"unlabelled.ply"}});
  EXPECT_EQ(j["input"], "data/train");
  EXPECT_EQ(j["model_file"], "out/model.json");
  EXPECT_EQ(j["model_sha256"], "abc123");
  ASSERT_EQ(j["comparison"].size(), 1u);
  EXPECT_EQ(j["comparison"][0]["family"], "invariants");
  EXPECT_DOUBLE_EQ(j["comparison"][0]["test_accuracy"].get<double>(), trained.report.test.accuracy);
  ASSERT_EQ(j["skipped"].size(), 2u);
  EXPECT_EQ(j["skipped"][0]["code"], "timeout");
  EXPECT_EQ(j["skipped"][1]["code"], "no_label");
  EXPECT_TRUE(j.contains("grid"));  // the report itself is all there
}

}  // namespace
}  // namespace wish
