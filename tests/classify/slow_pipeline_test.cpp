// Slow (maps meshes): the bundled default model on demo meshes; a rotated, translated copy of a mesh gets the
// same prediction (issue 5). Suite name Slow* so quick runs can filter it out.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/classify/classifier_model.hpp"
#include "core/pipeline/pipeline.hpp"
#include "core/synth/demo_dataset.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

TEST(SlowClassifyPipeline, RotatedTranslatedCopyGetsTheSamePrediction) {
  const auto path = testing::project_data_dir() / "models" / "default.json";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
  const ClassifierModel model = ClassifierModel::load(path);
  synth::DemoOptions demo;
  demo.seed = 4242;  // not the training seed
  const Mesh mesh = synth::generate_demo_nucleus(0, 0, demo).mesh;
  Mesh moved = mesh;
  const Eigen::Matrix3d R = testing::random_rotation(testing::test_seed());
  moved.vertices = (mesh.vertices * R.transpose()).rowwise() + Eigen::RowVector3d(12.5, -40, 3);
  const PipelineOptions po = options_for_recipe(model.recipe());
  const PipelineResult a = describe_mesh(mesh, po), b = describe_mesh(moved, po);
  const Prediction pa = model.predict(a.features), pb = model.predict(b.features);
  EXPECT_EQ(pa.label, pb.label);
  for (std::size_t i = 0; i < pa.probabilities.size(); ++i)
    EXPECT_NEAR(pa.probabilities[i].second, pb.probabilities[i].second, 0.05) << pa.probabilities[i].first;
  for (int l = 1; l < a.sh.invariants.size(); ++l)
    EXPECT_NEAR(a.sh.invariants(l), b.sh.invariants(l), 1e-3 * a.sh.invariants(1)) << "xi(" << l << ")";
}

}  // namespace
}  // namespace wish
