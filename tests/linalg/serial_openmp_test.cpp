// SerialOpenMpScope (serial_openmp.hpp): inside the scope a parallel region runs inline on the calling thread
// (outside any team: level 0) and a work-shared loop still covers every iteration once; outside the scope, and
// inside an enclosing parallel region, regions go to libgomp as before; the caller's OpenMP settings come back.
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "core/linalg/serial_openmp.hpp"

namespace wish::linalg {
namespace {

struct RegionSeen {
  int level = -1, team = -1, bodies = 0;
};

// One `omp parallel` region asking for two threads, as CHOLMOD's num_threads clause does.
RegionSeen two_thread_region() {
  RegionSeen seen;
#pragma omp parallel num_threads(2)
  {
#pragma omp critical
    {
      ++seen.bodies;
      seen.level = omp_get_level();
      seen.team = omp_get_num_threads();
    }
  }
  return seen;
}

// The same region as GCC's code and CHOLMOD's (built by GCC) enter it: a call of libgomp's entry point
// GOMP_parallel(body, data, num_threads, flags), the call the scope intercepts. Called directly, so that the test
// checks the interception also where this file is compiled by clang (the sanitizer build), whose own `omp parallel`
// goes to libomp's __kmpc_fork_call instead and never reaches GOMP_parallel.
extern "C" void GOMP_parallel(void (*body)(void*), void* data, unsigned num_threads, unsigned flags);

void record_region(void* data) {
  RegionSeen& seen = *static_cast<RegionSeen*>(data);
#pragma omp critical
  {
    ++seen.bodies;
    seen.level = omp_get_level();
    seen.team = omp_get_num_threads();
  }
}

RegionSeen two_thread_gomp_region() {
  RegionSeen seen;
  GOMP_parallel(&record_region, &seen, 2, 0);
  return seen;
}

TEST(SerialOpenMp, InsideTheScopeARegionRunsInlineOnce) {
  omp_set_dynamic(0);
  const SerialOpenMpScope scope;
  EXPECT_TRUE(SerialOpenMpScope::active());
  const RegionSeen seen = two_thread_gomp_region();
  EXPECT_EQ(seen.bodies, 1);
  EXPECT_EQ(seen.level, 0);  // no team was made: the body was called directly
  EXPECT_EQ(seen.team, 1);
}

TEST(SerialOpenMp, WorkSharedLoopsCoverEveryIterationOnceInsideTheScope) {
  const SerialOpenMpScope scope;
  std::vector<int> hits_static(1000, 0), hits_dynamic(1000, 0);
#pragma omp parallel for num_threads(4)
  for (int i = 0; i < 1000; ++i) ++hits_static[static_cast<size_t>(i)];
#pragma omp parallel for schedule(dynamic, 7) num_threads(4)
  for (int i = 0; i < 1000; ++i) ++hits_dynamic[static_cast<size_t>(i)];
  for (int i = 0; i < 1000; ++i) {
    EXPECT_EQ(hits_static[static_cast<size_t>(i)], 1) << i;
    EXPECT_EQ(hits_dynamic[static_cast<size_t>(i)], 1) << i;
  }
}

TEST(SerialOpenMp, OutsideTheScopeRegionsGoToTheRuntime) {
  EXPECT_FALSE(SerialOpenMpScope::active());
  omp_set_dynamic(0);
  const RegionSeen seen = two_thread_region();
  EXPECT_EQ(seen.level, 1);
  EXPECT_EQ(seen.team, 2);
  EXPECT_EQ(seen.bodies, 2);
}

TEST(SerialOpenMp, InsideAnEnclosingRegionTheScopeLeavesNestingToTheRuntime) {
  int inner_level = -1;
#pragma omp parallel num_threads(1)
  {
    const SerialOpenMpScope scope;
#pragma omp parallel num_threads(2)
    {
#pragma omp master
      inner_level = omp_get_level();
    }
  }
  EXPECT_EQ(inner_level, 2);  // a nested region (inactive or not) inside the outer one, not an inline call
}

TEST(SerialOpenMp, TheScopeRestoresTheCallersSettings) {
  omp_set_dynamic(0);
  omp_set_num_threads(3);
  {
    const SerialOpenMpScope scope;
    EXPECT_EQ(omp_get_max_threads(), 1);
  }
  EXPECT_FALSE(SerialOpenMpScope::active());
  EXPECT_EQ(omp_get_dynamic(), 0);
  EXPECT_EQ(omp_get_max_threads(), 3);
}

}  // namespace
}  // namespace wish::linalg
