#include "core/common/stage_profile.hpp"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <mutex>

namespace wish::profile {
namespace {

std::atomic<bool> g_enabled{false};
std::mutex g_mutex;
std::vector<StageTotal>& totals() {
  static std::vector<StageTotal> t;  // a few dozen names at most: a linear search is cheaper than a map
  return t;
}

double thread_cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

void enable_stage_profile(bool on) { g_enabled.store(on, std::memory_order_relaxed); }
bool stage_profile_enabled() { return g_enabled.load(std::memory_order_relaxed); }

void enable_stage_profile_from_environment() {
  const char* v = std::getenv("WISH_PROFILE");
  if (v && *v && std::strcmp(v, "0") != 0) enable_stage_profile(true);
}

void reset_stage_profile() {
  const std::lock_guard lock(g_mutex);
  totals().clear();
}

std::vector<StageTotal> stage_totals() {
  const std::lock_guard lock(g_mutex);
  return totals();
}

std::string stage_profile_table() {
  std::string out = "stage                               calls    wall s     cpu s\n";
  char line[160];
  for (const StageTotal& t : stage_totals()) {
    std::snprintf(line, sizeof line, "%-34s %6ld %9.4f %9.4f\n", t.name.c_str(), t.calls, t.wall_seconds, t.cpu_seconds);
    out += line;
  }
  return out;
}

ScopedStage::ScopedStage(const char* name) : name_(stage_profile_enabled() ? name : nullptr) {
  if (!name_) return;
  wall0_ = std::chrono::steady_clock::now();
  cpu0_ = thread_cpu_now();
}

ScopedStage::~ScopedStage() {
  if (!name_) return;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count();
  const double cpu = thread_cpu_now() - cpu0_;
  const std::lock_guard lock(g_mutex);
  for (StageTotal& t : totals())
    if (t.name == name_) {
      ++t.calls;
      t.wall_seconds += wall;
      t.cpu_seconds += cpu;
      return;
    }
  totals().push_back({name_, 1, wall, cpu});
}

}  // namespace wish::profile
