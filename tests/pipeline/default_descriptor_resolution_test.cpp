// Issue 37 items 1 and 3 on real meshes: the default descriptor (core/pipeline/default_pipeline_options.hpp: the
// cMCF chain, the canonical isometric map, the SH fit over the surface) of a mesh and of the same surface split by
// midpoint subdivision (identical geometry, 4× the faces) agree. Tolerance, stated: max over l = 1..10 of
// |Δ log ξ(l)| ≤ 0.15. Measured (bench/canonical_map_bench FILE --starts cmcf --subdivide 1 --sampling surface):
// 0.026 (hvcl spine_1), 0.013 (UroCell raw fv fib1-0-0-0_103), 0.035 (nmv nucleus-1 lq, 271 vertices); at the
// vertices instead of the surface the same meshes move by 0.264, 0.061 and 0.328 (docs/accuracy.md, issue 37 item 3),
// so the bound fails two of the three with the paper's vertex fit.
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/mesh/subdivision.hpp"
#include "core/pipeline/default_pipeline_options.hpp"
#include "core/pipeline/pipeline.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

constexpr double kResolutionTolerance = 0.15;  // max_l |Δ log ξ(l)|, l = 1..Lmax

double max_log_xi_change(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double worst = 0;
  for (Eigen::Index l = 1; l < a.size(); ++l) worst = std::max(worst, std::abs(std::log(a[l]) - std::log(b[l])));
  return worst;
}

class SlowDefaultDescriptorResolution : public ::testing::TestWithParam<std::string> {};

TEST_P(SlowDefaultDescriptorResolution, SubdividedSurfaceKeepsTheDescriptor) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const std::filesystem::path file = *testing::shared_data_dir() / GetParam();
  if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " not in this copy of the shared data";
  const Mesh mesh = read_mesh_file(file).mesh;
  const PipelineOptions options = default_pipeline_options();
  const PipelineResult coarse = describe_mesh(mesh, options);
  const PipelineResult fine = describe_mesh(subdivide_midpoint(mesh, 1), options);
  ASSERT_TRUE(coarse.map.ok());
  ASSERT_TRUE(fine.map.ok());
  ASSERT_EQ(coarse.sh.invariants.size(), fine.sh.invariants.size());
  const double change = max_log_xi_change(coarse.sh.invariants, fine.sh.invariants);
  RecordProperty("max_abs_dlog_xi", std::to_string(change));
  EXPECT_LE(change, kResolutionTolerance) << GetParam() << ": " << mesh.vertex_count() << " -> "
                                          << fine.prepared.mesh.vertex_count() << " vertices";
}

INSTANTIATE_TEST_SUITE_P(RealMeshes, SlowDefaultDescriptorResolution,
                         ::testing::Values("hard/hvcl_spines/spine_1.off", "urocell_raw_mc/fv/fib1-0-0-0_103.off",
                                           "nmv_nuclei/nuclei-meshes/lq/nucleus-1.obj"));

}  // namespace
}  // namespace wish
