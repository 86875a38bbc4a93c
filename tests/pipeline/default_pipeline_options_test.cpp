// The one default (core/pipeline/default_pipeline_options.hpp, issue 37 item 2): a mesh described with no options
// gets exactly the descriptor a model trained with no options computes for it, on the same chain.
#include <gtest/gtest.h>

#include "core/classify/default_recipe.hpp"
#include "core/pipeline/default_pipeline_options.hpp"
#include "core/pipeline/pipeline.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

Mesh read_project_mesh(const std::string& name) {
  return read_mesh_file(testing::project_data_dir() / "meshes" / name).mesh;
}

TEST(DefaultPipelineOptions, DescribeByDefaultGivesTheDescriptorTheDefaultModelUses) {
  const Mesh mesh = read_project_mesh("celegans_cell.obj");
  const PipelineResult described = describe_mesh(mesh, default_pipeline_options());
  const PipelineResult trained = describe_mesh(mesh, options_for_recipe(default_training_recipe()));
  ASSERT_TRUE(described.map.ok());
  EXPECT_EQ(described.map.method_used, trained.map.method_used);
  EXPECT_EQ(described.map.chosen_attempt, trained.map.chosen_attempt);
  EXPECT_EQ(described.map.canonical.method, default_training_recipe().map.canonical.method);
  EXPECT_EQ(described.sh.lmax, default_training_recipe().sh.lmax);
  ASSERT_EQ(described.sh.invariants.size(), trained.sh.invariants.size());
  for (Eigen::Index l = 0; l < described.sh.invariants.size(); ++l)
    EXPECT_DOUBLE_EQ(described.sh.invariants[l], trained.sh.invariants[l]) << "l=" << l;
  // The descriptor's map is the default model's: check_recipe accepts it (no off-recipe loss by default).
  EXPECT_TRUE(check_recipe(default_training_recipe(), described.map).match);
}

TEST(DefaultPipelineOptions, ThePapersSettingsStayTheStructDefaults) {
  // PipelineOptions{} is the paper's flow and the fit's own settings (the closest fit); the default of every front
  // end differs from it by the recipe only, so `--method willmore --canonical none --lmax 15 --regularization 1e-5`
  // (what `wish describe --help` prints from PipelineOptions{}) gives the paper's descriptor back.
  const PipelineOptions paper;
  const PipelineOptions defaults = default_pipeline_options();
  EXPECT_EQ(paper.map.method, MapMethod::Willmore);
  EXPECT_EQ(paper.map.canonical.method, CanonicalMap::None);
  EXPECT_NE(defaults.map.method, paper.map.method);
  EXPECT_EQ(defaults.read.limits.max_bytes, paper.read.limits.max_bytes);
  EXPECT_FALSE(defaults.compute_global_features);  // a description needs no feature blocks
}

}  // namespace
}  // namespace wish
