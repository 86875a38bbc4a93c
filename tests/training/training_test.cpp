#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/classify/feature_pipeline.hpp"
#include "core/classify/splits.hpp"
#include "core/common/errors.hpp"
#include "core/training/training.hpp"
#include "core/training/training_report.hpp"
#include "tests/classify/classify_test_data.hpp"

namespace wish {
namespace {

TEST(Splits, StratifiedShuffleSplitKeepsProportions) {
  std::vector<int> y;
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 10 + 5 * c; ++i) y.push_back(c);
  const auto splits = stratified_shuffle_split(y, 5, 0.2, 3);
  ASSERT_EQ(splits.size(), 5u);
  for (const auto& s : splits) {
    EXPECT_EQ(s.test.size(), 9u);  // ceil(0.2 * 45)
    EXPECT_EQ(s.train.size() + s.test.size(), y.size());
    std::vector<int> count(3, 0);
    for (int i : s.test) ++count[y[i]];
    EXPECT_EQ(count, (std::vector<int>{2, 3, 4}));
    std::set<int> all(s.train.begin(), s.train.end());
    all.insert(s.test.begin(), s.test.end());
    EXPECT_EQ(all.size(), y.size());
  }
  EXPECT_NE(splits[0].test, splits[1].test);
  EXPECT_EQ(stratified_shuffle_split(y, 5, 0.2, 3)[4].test, splits[4].test);  // seed-determined
}

TEST(Splits, KFoldCoversEverySampleOnce) {
  std::vector<int> y(23);
  for (int i = 0; i < 23; ++i) y[i] = i % 4;
  const auto folds = stratified_k_fold(y, 5, 9);
  std::vector<int> seen(23, 0);
  for (const auto& f : folds)
    for (int i : f.test) ++seen[i];
  EXPECT_EQ(seen, std::vector<int>(23, 1));
}

TEST(FeaturePipeline, SelectsNormalisesAndLogs) {
  ShapeFeatures f;
  f.invariants = Eigen::VectorXd::LinSpaced(6, 1, 6);  // xi(l) = l + 1
  f.global = Eigen::VectorXd::Constant(kGlobalCount, 2.0);
  FeatureSpec spec;
  spec.l_min = 2;
  spec.l_max = 4;
  spec.scale = ScaleNormalization::ByFirstInvariant;
  spec.log_transform = true;
  const Eigen::VectorXd v = apply_feature_pipeline(f, spec);
  ASSERT_EQ(v.size(), 3);
  EXPECT_DOUBLE_EQ(v(0), std::log(3.0 / 2.0));
  EXPECT_DOUBLE_EQ(v(2), std::log(5.0 / 2.0));
  spec.scale = ScaleNormalization::ByArea;
  spec.log_transform = false;
  spec.family = FeatureFamily::Combined;
  spec.global_scale_free = true;
  const Eigen::VectorXd w = apply_feature_pipeline(f, spec);
  EXPECT_EQ(w.size(), 3 + kGlobalCount - 3);
  EXPECT_DOUBLE_EQ(w(0), 1.5);
  EXPECT_EQ(feature_names(spec).front(), "xi_2");
  EXPECT_EQ(feature_names(spec)[3], "g_sphericity");
  f.global.resize(0);
  EXPECT_THROW(apply_feature_pipeline(f, spec), InvalidInputError);
}

TEST(Training, ReproducibleWithASeed) {
  const auto samples = testing::synthetic_samples(3, 14, 21);
  const auto a = train_classifier(samples, testing::quick_train_options(5));
  const auto b = train_classifier(samples, testing::quick_train_options(5));
  EXPECT_EQ(a.model.to_json_text(), b.model.to_json_text());
  EXPECT_EQ(a.report.nested.scores, b.report.nested.scores);
  EXPECT_EQ(a.report.test_indices, b.report.test_indices);
}

TEST(Training, ReportsTheFiguresOfTable1AndMore) {
  const auto samples = testing::synthetic_samples(3, 20, 22);
  auto opts = testing::quick_train_options(6);
  const auto r = train_classifier(samples, opts);
  const TrainingReport& rep = r.report;
  EXPECT_EQ(rep.classes, (std::vector<std::string>{"class_a", "class_b", "class_c"}));
  EXPECT_EQ(rep.grid.mean_score.rows(), 5);
  EXPECT_EQ(rep.grid.mean_score.cols(), 5);
  double best_not_offset = -1;  // the best cell is the best of those not decided by the SVM's offset
  for (int c = 0; c < rep.grid.mean_score.rows(); ++c)
    for (int g = 0; g < rep.grid.mean_score.cols(); ++g)
      if (!rep.grid.cell_offset_decided(c, g)) best_not_offset = std::max(best_not_offset, rep.grid.mean_score(c, g));
  EXPECT_DOUBLE_EQ(rep.grid.best_score, best_not_offset);
  EXPECT_GT(rep.grid.best_score, 0.5);  // chance is 1/3
  EXPECT_EQ(rep.test.confusion.sum(), static_cast<int>(rep.test_indices.size()));
  EXPECT_EQ(rep.test_indices.size(), 12u);  // ceil(0.2 * 60)
  EXPECT_EQ(rep.nested.scores.size(), 3u);
  ASSERT_EQ(rep.nested.inner_scores.size(), rep.nested.scores.size());  // one inner search per outer fold
  for (double inner : rep.nested.inner_scores) EXPECT_TRUE(inner > 0 && inner <= 1);
  EXPECT_EQ(r.model.training_summary().best_c, rep.grid.C());
  EXPECT_EQ(r.model.training_summary().samples, 60);
  const std::string table = training_report_table(rep);  // the JSON report: tests/wire/training_report_json_test
  EXPECT_NE(table.find("precision"), std::string::npos);
  const std::string svg = grid_heatmap_svg(rep.grid, "test");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
}

// A model that merged classes says so: trained only at the tiny-C corner (every cell decided by the SVM's offset) on
// unbalanced classes (6, 6, 6, 6, 9, 9 samples), the shipped model predicts its training rows as a few classes; the
// report names the others and warns. The default grid on the same samples predicts every class.
TEST(Training, ReportsClassesTheModelNeverPredicts) {
  std::vector<TrainingSample> samples;
  int kept[6] = {0, 0, 0, 0, 0, 0};
  for (auto& s : testing::synthetic_samples(6, 9, 40, 8, 0.9)) {
    const int c = s.label.back() - 'a';
    if (c >= 4 || kept[c]++ < 6) samples.push_back(std::move(s));
  }
  auto corner = testing::quick_train_options(3);
  corner.grid.Cs = {1e-2};
  corner.grid.gammas = {1e-9};
  corner.nested_repeats = 0;
  const auto merged = train_classifier(samples, corner);
  EXPECT_TRUE(merged.report.grid.best_offset_decided);
  ASSERT_FALSE(merged.report.train_classes_never_predicted.empty());
  EXPECT_LT(merged.report.train_accuracy, 0.5);
  const std::string table = training_report_table(merged.report);
  EXPECT_NE(table.find("WARNING: the model predicts none of its training samples as"), std::string::npos) << table;
  EXPECT_NE(table.find("WARNING: the chosen cell is decided by the offset"), std::string::npos) << table;
  auto wide = corner;
  wide.grid.Cs = decade_grid(-2, 6);
  wide.grid.gammas = decade_grid(-9, 1);
  const auto fine = train_classifier(samples, wide);
  EXPECT_FALSE(fine.report.grid.best_offset_decided);
  EXPECT_TRUE(fine.report.train_classes_never_predicted.empty()) << training_report_table(fine.report);
}

TEST(Training, FamiliesAndRefit) {
  const auto samples = testing::synthetic_samples(2, 12, 23);
  for (auto family : {FeatureFamily::Invariants, FeatureFamily::Global, FeatureFamily::Combined}) {
    auto opts = testing::quick_train_options(8);
    opts.nested_repeats = 0;
    opts.recipe.features.family = family;
    opts.refit_on_all = family == FeatureFamily::Combined;
    const auto r = train_classifier(samples, opts);
    EXPECT_EQ(r.model.needs_global_features(), family != FeatureFamily::Invariants);
    EXPECT_NO_THROW((void)r.model.predict(samples[0].features));
  }
}

TEST(Training, RefusesUnusableData) {
  auto samples = testing::synthetic_samples(2, 6, 24);
  auto opts = testing::quick_train_options();
  for (auto& s : samples) s.label = "same";
  EXPECT_THROW(train_classifier(samples, opts), InvalidInputError);
  samples = testing::synthetic_samples(2, 6, 24);
  samples[0].features.invariants.resize(3);
  EXPECT_THROW(train_classifier(samples, opts), InvalidInputError);
}

// Training never hides losses (issue 12): per class, meshes lost by error code; a class over the limit stops
// training with a message naming it, unless losses are allowed.
std::vector<MeshLoss> losses_of(const std::string& label, int n, const std::string& code) {
  std::vector<MeshLoss> out;
  for (int i = 0; i < n; ++i) out.push_back({label + "_lost_" + std::to_string(i), label, code, "test"});
  return out;
}

TEST(TrainingLosses, CountedPerClassAndCode) {
  const std::vector<std::string> kept{"a", "a", "a", "b", "b"};
  auto losses = losses_of("a", 2, "map_failed");
  losses.push_back({"x", "a", "off_recipe", ""});
  losses.push_back({"y", "c", "degenerate_faces", ""});  // a class that lost every mesh still appears
  const auto rows = summarize_losses(kept, losses, {"b"});
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].label, "a");
  EXPECT_EQ(rows[0].total, 6);
  EXPECT_EQ(rows[0].kept, 3);
  EXPECT_EQ(rows[0].lost_by_code.at("map_failed"), 2);
  EXPECT_EQ(rows[0].lost_by_code.at("off_recipe"), 1);
  EXPECT_DOUBLE_EQ(rows[0].lost_share(), 0.5);
  EXPECT_EQ(rows[1].flagged, 1);
  EXPECT_EQ(rows[1].lost(), 0);
  EXPECT_EQ(rows[2].total, 1);
  EXPECT_EQ(rows[2].kept, 0);
  const std::string table = loss_table(rows);
  EXPECT_NE(table.find("map_failed x2"), std::string::npos) << table;
  EXPECT_NE(table.find("degenerate_faces x1"), std::string::npos) << table;
}

TEST(TrainingLosses, StopsWhenAClassLosesMoreThanTheLimit) {
  const auto samples = testing::synthetic_samples(2, 12, 31);  // 12 per class kept
  auto opts = testing::quick_train_options();
  opts.nested_repeats = 0;
  opts.losses = losses_of("class_a", 1, "map_failed");  // 1 of 13: 7.7 % <= 10 %
  const auto ok = train_classifier(samples, opts);
  ASSERT_EQ(ok.report.losses.size(), 2u);
  EXPECT_EQ(ok.report.losses[0].lost(), 1);
  EXPECT_NE(training_report_table(ok.report).find("map_failed x1"), std::string::npos);

  opts.losses = losses_of("class_b", 2, "map_failed");  // 2 of 14: 14.3 % > 10 %
  opts.losses.push_back({"z", "class_b", "off_recipe", ""});
  try {
    (void)train_classifier(samples, opts);
    FAIL() << "trained although class_b lost 3 of 15 meshes";
  } catch (const InvalidInputError& e) {
    EXPECT_EQ(e.code(), "training_losses");
    const std::string m = e.what();
    EXPECT_NE(m.find("class_b: 3 of 15 lost"), std::string::npos) << m;
    EXPECT_NE(m.find("map_failed x2"), std::string::npos) << m;
    EXPECT_NE(m.find("off_recipe x1"), std::string::npos) << m;
    EXPECT_EQ(m.find("class_a:"), std::string::npos) << m;
  }
  opts.loss_policy.max_class_loss = 0.25;  // a configured limit
  EXPECT_NO_THROW((void)train_classifier(samples, opts));
  opts.loss_policy.max_class_loss = 0.1;
  opts.loss_policy.allow_losses = true;  // told to train anyway: the report still shows the losses
  const auto allowed = train_classifier(samples, opts);
  EXPECT_EQ(allowed.report.losses[1].lost(), 3);
}

}  // namespace
}  // namespace wish
