#include <gtest/gtest.h>

#include "core/common/stage_profile.hpp"

namespace wish::profile {
namespace {

const StageTotal* find(const std::vector<StageTotal>& totals, const std::string& name) {
  for (const StageTotal& t : totals)
    if (t.name == name) return &t;
  return nullptr;
}

TEST(StageProfile, RecordsOnlyWhileEnabledAndSumsCallsPerName) {
  reset_stage_profile();
  enable_stage_profile(false);
  { const ScopedStage s("off"); }
  EXPECT_EQ(find(stage_totals(), "off"), nullptr);  // off: nothing is recorded

  enable_stage_profile(true);
  for (int i = 0; i < 3; ++i) {
    const ScopedStage outer("outer");
    volatile double sink = 0;
    for (int k = 0; k < 100000; ++k) sink = sink + k;
    const ScopedStage inner("inner");
  }
  enable_stage_profile(false);
  const std::vector<StageTotal> totals = stage_totals();
  const StageTotal* outer = find(totals, "outer");
  const StageTotal* inner = find(totals, "inner");
  ASSERT_NE(outer, nullptr);
  ASSERT_NE(inner, nullptr);
  EXPECT_EQ(outer->calls, 3);
  EXPECT_EQ(inner->calls, 3);
  EXPECT_GE(outer->wall_seconds, inner->wall_seconds);  // rows are inclusive of the stages they contain
  EXPECT_GE(outer->cpu_seconds, 0.0);
  EXPECT_EQ(totals.front().name, "inner");  // the order in which stages first finished
  EXPECT_NE(stage_profile_table().find("outer"), std::string::npos);
  reset_stage_profile();
  EXPECT_TRUE(stage_totals().empty());
}

}  // namespace
}  // namespace wish::profile
