#pragma once
// Wall and thread-CPU seconds per named stage of a run (issue 28: where a map's time goes), off by default.
// `WISH_PROFILE=1 wish map ...` turns it on for a CLI run and prints the table to stderr at exit; a bench or a test
// may call enable_stage_profile(). Off, a ScopedStage costs one relaxed atomic load: the hot loops keep no clock.
// Stages may nest (a flow step contains its factorisations): each row is inclusive of the rows it contains, so
// nested rows are not to be summed with their parent. Thread-safe (one mutex, taken only while enabled).

#include <chrono>
#include <string>
#include <vector>

namespace wish::profile {

struct StageTotal {
  std::string name;
  long calls = 0;
  double wall_seconds = 0;
  double cpu_seconds = 0;  // CPU time of the thread that ran the stage
};

void enable_stage_profile(bool on = true);
bool stage_profile_enabled();
// Turns the profile on when the environment variable WISH_PROFILE is set to a non-empty value other than "0".
void enable_stage_profile_from_environment();
void reset_stage_profile();
// The totals in the order in which each stage first finished (a nested stage before its parent).
std::vector<StageTotal> stage_totals();
// A fixed-width text table of stage_totals().
std::string stage_profile_table();

class ScopedStage {
 public:
  explicit ScopedStage(const char* name);
  ~ScopedStage();
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;

 private:
  const char* name_;  // null when the profile was off at construction
  std::chrono::steady_clock::time_point wall0_;
  double cpu0_ = 0;
};

}  // namespace wish::profile
