#pragma once
// Wall seconds since a steady-clock instant: the stage timings the results report (flow, factorisation, solve, fit).
// One definition for every area, so that files which time their stages can share a unity batch
// (cmake/WishBuildSpeed.cmake) instead of each defining its own helper.

#include <chrono>

namespace wish {

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace wish
