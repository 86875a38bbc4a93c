// Issue 39 item 1: hard single-object masks (tests/synth/hard_masks.hpp) gives exactly one object with no
// flags, meshed genus 0: written as an 8-bit NIfTI and read by the default label-volume path (core/pipeline
// describe_volume with default VolumeOptions, as `wish train` / `wish predict` read a file). Prints the table of what
// the defaults did per mask (specks dropped, fragments merged, genus, repair, volume change) for docs/accuracy.md.
// The UroCell-derived masks (../shared/data) are tests/synth/hard_masks_sweep_test.cpp (slow).
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/synth/hard_masks.hpp"

namespace wish::testing {
namespace {

// A sample of each family here (about 5 s); all 60 in tests/synth/hard_masks_sweep_test.cpp (slow).
TEST(HardMasks, ASampleOfEachFamilyIsOneObjectMeshedGenusZeroWithNoFlags) {
  print_outcome_header();
  std::vector<HardMask> sample = {drilled_mask(1, 1, false), drilled_mask(3, 2, true), drilled_mask(5, 3, false),
                                  y_touch_mask(2, 0.5), y_touch_mask(4, 2), cavity_mask(3)};
  for (int cls = 0; cls < 6; ++cls) sample.push_back(soft_demo_mask(cls, 11, 6));
  for (const HardMask& m : sample) {
    const HardMaskOutcome o = default_path_outcome(m);
    print_outcome_row(m, o);
    EXPECT_EQ(o.kept, 1) << m.name;
    EXPECT_TRUE(o.ok) << m.name << ": " << o.refusal;
    if (m.expected_genus >= 0) EXPECT_EQ(o.genus, m.expected_genus) << m.name;
    if (m.family == "soft_demo") EXPECT_GE(o.specks + o.fragments, 1) << m.name << ": the specks must have been seen";
  }
}

}  // namespace
}  // namespace wish::testing
