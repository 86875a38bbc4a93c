// The training driver (core/training/training_run.hpp) on small inputs written to a temporary directory: a
// descriptor CSV of xi alone (the fallback to the invariants family, said in a note; a chosen family that needs the
// global descriptors refused; an Lmax above the CSV's refused; labels joined from a manifest, unlabelled rows kept
// out and reported), and a class directory of generated ellipsoids described with the default recipe (its canonical
// map counted, every item told).
#include "core/training/training_run.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "core/classify/default_recipe.hpp"
#include "core/classify/feature_pipeline.hpp"
#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

namespace fs = std::filesystem;

class RunDir {
 public:
  RunDir() {
    path_ = fs::temp_directory_path() /
            ("wish_training_run_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~RunDir() { fs::remove_all(path_); }
  RunDir(const RunDir&) = delete;
  RunDir& operator=(const RunDir&) = delete;
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return path_ / name;
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

constexpr int kCsvLmax = 6;

// Two classes whose energies decay at different rates (separable), `per_class` rows each, xi_0..xi_6 and no g_*
// columns: what `wish describe --csv` wrote before --save-descriptors kept the global descriptors. With
// `label_column` false the rows carry no label (a manifest gives them).
std::string xi_only_csv(int per_class, bool label_column = true) {
  std::mt19937 rng(testing::test_seed(7));
  std::uniform_real_distribution<double> jitter(0.9, 1.1);
  std::ostringstream csv;
  csv << "file" << (label_column ? ",label" : "");
  for (int l = 0; l <= kCsvLmax; ++l) csv << ",xi_" << l;
  csv << "\n";
  for (const std::string label : {"round", "long"}) {
    const double decay = label == "round" ? 2.0 : 0.7;
    for (int i = 0; i < per_class; ++i) {
      csv << label << i << ".obj" << (label_column ? "," + label : "");
      for (int l = 0; l <= kCsvLmax; ++l) csv << "," << std::exp(-decay * l) * jitter(rng);
      csv << "\n";
    }
  }
  return csv.str();
}

// Small and quick: a 2 x 2 grid, two splits, no nested CV.
TrainingRunRequest small_request(const fs::path& input, int lmax) {
  TrainingRunRequest r;
  r.input = input.string();
  r.recipe = default_training_recipe();  // family combined: needs the global descriptors
  r.recipe.features.l_min = kMinFeatureLmax;
  r.recipe.features.l_max = lmax;
  r.recipe.sh.lmax = lmax;
  r.describe_jobs = 1;
  r.train.grid.Cs = {1, 100};
  r.train.grid.gammas = {0.01, 1};
  r.train.grid.jobs = 1;
  r.train.grid_splits = 2;
  r.train.nested_repeats = 0;
  return r;
}

// The code and message of the WishError `f` throws ("", "" when it throws none).
template <class F>
std::pair<std::string, std::string> refusal(F f) {
  try {
    f();
  } catch (const WishError& e) {
    return {e.code(), e.what()};
  }
  return {"", ""};
}

bool contains(const std::vector<std::string>& lines, const std::string& part) {
  return std::any_of(lines.begin(), lines.end(), [&](const std::string& l) { return l.find(part) != std::string::npos; });
}

TEST(TrainingRun, DescriptorCsvWithoutGlobalColumnsFallsBackToInvariantsAndSaysSo) {
  RunDir dir;
  TrainingRunRequest r = small_request(dir.write("xi.csv", xi_only_csv(12)), 4);
  ASSERT_TRUE(r.recipe.needs_global_features()) << "the default family must need g_* for this test to mean anything";
  std::vector<std::string> events;  // notes and the gathered-samples call, in order
  r.events.note = [&](const std::string& line) { events.push_back(line); };
  std::size_t gathered = 0;
  r.events.samples_gathered = [&](const std::vector<TrainingSample>& s) {
    gathered = s.size();
    events.push_back("<samples gathered>");
  };
  bool trained_told = false;
  r.events.model_trained = [&](const TrainingResult&) { trained_told = true; };
  r.events.summary = [&](const std::string& line) { ADD_FAILURE() << "no canonical summary for a CSV: " << line; };

  const TrainingRunResult run = run_training(r);
  EXPECT_TRUE(run.fell_back_to_invariants);
  EXPECT_FALSE(run.has_global);
  EXPECT_EQ(run.trained.model.feature_spec().family, FeatureFamily::Invariants);
  EXPECT_EQ(run.trained.model.feature_spec().l_max, 4);
  EXPECT_EQ(run.trained.model.recipe().sh.lmax, kCsvLmax) << "the model records the CSV's fit, not the request's";
  EXPECT_EQ(run.samples, 24u);
  EXPECT_EQ(gathered, 24u);
  EXPECT_TRUE(trained_told);
  EXPECT_FALSE(run.canonical_unconverged.has_value());
  ASSERT_EQ(run.families.size(), 1u) << "without g_* columns there is nothing to compare";
  EXPECT_EQ(run.families[0].family, "invariants");
  // Said, not silent, and in the CLI's order: what was read, the samples (saved), the fallback, then training.
  const auto at = [&](const std::string& part) {
    return std::find_if(events.begin(), events.end(), [&](const std::string& l) { return l.find(part) != std::string::npos; }) -
           events.begin();
  };
  ASSERT_TRUE(contains(events, "read 24 labelled descriptors (xi_0..xi_6)"));
  ASSERT_TRUE(contains(events, "has no global descriptors (g_* columns): training with features invariants instead of "
                               "the default combined"));
  ASSERT_TRUE(contains(events, "training on 24 samples, features invariants"));
  EXPECT_LT(at("read 24"), at("<samples gathered>"));
  EXPECT_LT(at("<samples gathered>"), at("has no global descriptors"));
  EXPECT_LT(at("has no global descriptors"), at("training on"));
}

TEST(TrainingRun, AChosenFamilyThatNeedsGlobalDescriptorsIsRefusedOnAnXiOnlyCsv) {
  RunDir dir;
  TrainingRunRequest r = small_request(dir.write("xi.csv", xi_only_csv(6)), 4);
  r.family_chosen = true;
  bool gathered = false;
  r.events.samples_gathered = [&](const std::vector<TrainingSample>&) { gathered = true; };
  const auto [code, message] = refusal([&] { run_training(r); });
  EXPECT_EQ(code, "training_data");
  EXPECT_NE(message.find("--features combined needs the global descriptors (g_* columns)"), std::string::npos) << message;
  EXPECT_TRUE(gathered) << "the samples are handed out (e.g. saved) before the features are checked";
}

TEST(TrainingRun, AnLmaxAboveTheCsvsColumnsIsRefused) {
  RunDir dir;
  TrainingRunRequest r = small_request(dir.write("xi.csv", xi_only_csv(6)), kCsvLmax + 1);
  const auto [code, message] = refusal([&] { run_training(r); });
  EXPECT_EQ(code, "training_data");
  EXPECT_NE(message.find("--lmax 7 exceeds the CSV's xi_6"), std::string::npos) << message;
  // The CSV's own Lmax is fine.
  r.recipe.features.l_max = kCsvLmax;
  r.recipe.features.family = FeatureFamily::Invariants;
  EXPECT_EQ(run_training(r).trained.model.feature_spec().l_max, kCsvLmax);
}

TEST(TrainingRun, LabelsComeFromAManifestAndUnlabelledRowsAreReported) {
  RunDir dir;
  const fs::path csv = dir.write("xi.csv", xi_only_csv(8, false));
  // Every row but long7.obj, by file name relative to the manifest's directory.
  std::ostringstream manifest;
  manifest << "path,label\n";
  for (int i = 0; i < 8; ++i) manifest << "round" << i << ".obj,round\n";
  for (int i = 0; i < 7; ++i) manifest << "long" << i << ".obj,long\n";
  TrainingRunRequest r = small_request(csv, 4);
  r.labels = dir.write("labels.csv", manifest.str()).string();
  r.recipe.features.family = FeatureFamily::Invariants;
  r.family_chosen = true;
  std::vector<std::string> notes;
  r.events.note = [&](const std::string& line) { notes.push_back(line); };
  const TrainingRunResult run = run_training(r);
  EXPECT_FALSE(run.fell_back_to_invariants) << "the family was chosen and needs no g_*";
  EXPECT_EQ(run.samples, 15u);
  EXPECT_EQ(run.unlabelled, std::vector<std::string>{"long7.obj"});
  EXPECT_TRUE(contains(notes, "wish train: skipped long7.obj: no label"));
  EXPECT_EQ(run.trained.model.classes(), (std::vector<std::string>{"long", "round"}));
}

TEST(TrainingRun, AClassDirectoryIsDescribedWithTheRecipeAndItsCanonicalMapCounted) {
  RunDir dir;
  // Two classes of generated ellipsoids (near-spheres and elongated ones), small meshes: the default recipe's
  // whole chain (cMCF map, canonical isometric relaxation, SH fit, global descriptors) runs on each.
  const int per_class = 5;
  for (int i = 0; i < per_class; ++i) {
    fs::create_directories(dir.path() / "round");
    fs::create_directories(dir.path() / "long");
    write_mesh_file(testing::make_ellipsoid(1.0, 1.0 + 0.05 * i, 1.0, 2), dir.path() / "round" / ("r" + std::to_string(i) + ".obj"));
    write_mesh_file(testing::make_ellipsoid(2.5 + 0.1 * i, 1.0, 0.8, 2), dir.path() / "long" / ("l" + std::to_string(i) + ".obj"));
  }
  TrainingRunRequest r = small_request(dir.path(), 4);
  ASSERT_NE(r.recipe.map.canonical.method, CanonicalMap::None);
  r.compare_families = false;
  std::vector<std::string> notes, summary, items;
  r.events.note = [&](const std::string& line) { notes.push_back(line); };
  r.events.summary = [&](const std::string& line) { summary.push_back(line); };
  r.events.item_described = [&](const std::string& line, bool) { items.push_back(line); };
  const TrainingRunResult run = run_training(r);

  EXPECT_TRUE(contains(notes, "describing 10 files (Lmax 4, "));
  EXPECT_EQ(items.size(), 10u) << "one progress line per item";
  EXPECT_TRUE(run.losses.empty()) << run.losses.front().id << ": " << run.losses.front().message;
  EXPECT_EQ(run.samples, 10u);
  EXPECT_TRUE(run.has_global);
  EXPECT_FALSE(run.fell_back_to_invariants);
  EXPECT_EQ(run.trained.model.feature_spec().family, r.recipe.features.family);
  ASSERT_TRUE(run.canonical_unconverged.has_value());
  ASSERT_EQ(summary.size(), 1u);
  EXPECT_NE(summary[0].find("canonical map: " + std::to_string(10 - *run.canonical_unconverged) + " of 10 relaxations "
                            "converged; " + std::to_string(*run.canonical_unconverged) + " stopped"),
            std::string::npos)
      << summary[0];
  ASSERT_EQ(run.families.size(), 1u) << "compare_families false: the trained family alone";
}

TEST(TrainingRun, AClassDirectoryWithoutInputsIsRefused) {
  RunDir dir;
  fs::create_directories(dir.path() / "empty_class");
  const auto [code, message] = refusal([&] { run_training(small_request(dir.path(), 4)); });
  EXPECT_EQ(code, "training_data");
  EXPECT_NE(message.find("no meshes or label volumes"), std::string::npos) << message;
}

}  // namespace
}  // namespace wish
