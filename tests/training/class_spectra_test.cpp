// Per-class spectra of a training set: analytic values on hand-made samples, and that a trained model carries
// them through its file (and older files without them still load, with none).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/classify/classifier_model.hpp"
#include "core/training/class_spectra.hpp"
#include "tests/classify/classify_test_data.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

TrainingSample sample(const std::string& label, std::vector<double> xi) {
  TrainingSample s;
  s.label = label;
  s.features.invariants = Eigen::Map<Eigen::VectorXd>(xi.data(), static_cast<Eigen::Index>(xi.size()));
  return s;
}

TEST(ClassSpectra, MeanAndStdOfLogXiPerClassFromDegreeOne) {
  // Class "a": xi(l) = e and e^3 at l = 1 (ln 1 and 3: mean 2, population std 1), constant 0.5 at l = 2.
  // xi(0) is never used (it depends on translation). Class "b" has one sample: std 0. Label "z" is not a class.
  const std::vector<TrainingSample> samples{
      sample("a", {100.0, std::exp(1.0), 0.5}), sample("a", {7.0, std::exp(3.0), 0.5}),
      sample("b", {1.0, 2.0, 4.0}), sample("z", {1.0, 1.0, 1.0})};
  const auto spectra = class_spectra(samples, {"a", "b", "c"});
  ASSERT_EQ(spectra.size(), 3u);
  EXPECT_EQ(spectra[0].label, "a");
  EXPECT_EQ(spectra[0].count, 2);
  ASSERT_EQ(spectra[0].log_xi_mean.size(), 2u);
  EXPECT_NEAR(spectra[0].log_xi_mean[0], 2.0, 1e-14);
  EXPECT_NEAR(spectra[0].log_xi_std[0], 1.0, 1e-14);
  EXPECT_NEAR(spectra[0].log_xi_mean[1], std::log(0.5), 1e-14);
  EXPECT_NEAR(spectra[0].log_xi_std[1], 0.0, 1e-14);
  EXPECT_EQ(spectra[1].count, 1);
  EXPECT_NEAR(spectra[1].log_xi_mean[1], std::log(4.0), 1e-14);
  EXPECT_EQ(spectra[1].log_xi_std, (std::vector<double>{0.0, 0.0}));
  EXPECT_EQ(spectra[2].count, 0);  // a class with no samples: empty, not NaN
  EXPECT_TRUE(spectra[2].log_xi_mean.empty());
}

TEST(ClassSpectra, ZeroEnergyStaysFinite) {
  const auto spectra = class_spectra({sample("a", {1.0, 0.0, 1.0})}, {"a"});
  ASSERT_EQ(spectra[0].log_xi_mean.size(), 2u);
  EXPECT_TRUE(std::isfinite(spectra[0].log_xi_mean[0]));
  EXPECT_NEAR(spectra[0].log_xi_mean[0], std::log(1e-300), 1e-9);
}

TEST(ClassSpectra, TrainedModelCarriesThemThroughItsFile) {
  auto opts = testing::quick_train_options();
  opts.nested_repeats = 0;
  const auto samples = testing::synthetic_samples(3, 12, 11);
  const ClassifierModel model = train_classifier(samples, opts).model;
  const auto& spectra = model.training_summary().class_spectra;
  ASSERT_EQ(spectra.size(), model.classes().size());
  const auto expected = class_spectra(samples, model.classes());
  const auto path = std::filesystem::temp_directory_path() / "wish_class_spectra_test.json";
  model.save(path);
  const ClassifierModel loaded = ClassifierModel::load(path);
  std::filesystem::remove(path);
  const auto& again = loaded.training_summary().class_spectra;
  ASSERT_EQ(again.size(), expected.size());
  for (std::size_t c = 0; c < expected.size(); ++c) {
    EXPECT_EQ(again[c].label, model.classes()[c]);
    EXPECT_EQ(again[c].count, 12);
    EXPECT_EQ(again[c].log_xi_mean, expected[c].log_xi_mean);  // JSON keeps doubles exactly (round trip)
    EXPECT_EQ(again[c].log_xi_std, expected[c].log_xi_std);
  }
}

TEST(ClassSpectra, ModelFileWithoutThemLoadsWithNone) {
  const auto v1 = testing::project_data_dir().parent_path() / "tests" / "classify" / "data" / "model_format_v1.json";
  if (!std::filesystem::exists(v1)) GTEST_SKIP() << v1 << " not found";
  EXPECT_TRUE(ClassifierModel::load(v1).training_summary().class_spectra.empty());
}

}  // namespace
}  // namespace wish
