#pragma once
// A soft budget of CPU time spent by the CALLING THREAD (clock_gettime(CLOCK_THREAD_CPUTIME_ID)), for limits that
// must not depend on machine load: a wall-clock budget cuts a computation short when other processes share the
// cores, so the same input would end on a different method under load (issue 11). The sparse solvers of the map
// (CHOLMOD, OpenBLAS with one thread per worker) run on the calling thread, so its CPU clock counts their work and
// nothing else. Time spent sleeping, blocked or descheduled is not counted. Default-constructed: unlimited.
// (Deadline, deadline.hpp, stays the hard wall-clock limit of a request.)

#include <time.h>

#include <chrono>
#include <limits>

namespace wish {

class CpuBudget {
 public:
  CpuBudget() = default;  // unlimited: never expired

  // A budget of `seconds` of this thread's CPU time, counted from now. Only the thread that made it may query it
  // (another thread's CPU clock is a different clock).
  static CpuBudget for_this_thread(std::chrono::duration<double> seconds) {
    CpuBudget b;
    b.limit_ = thread_cpu_seconds() + seconds.count();
    b.limited_ = true;
    return b;
  }

  // The same clock stopped `seconds` earlier (a share kept in reserve for later work; unlimited stays unlimited).
  CpuBudget with_reserve(double seconds) const {
    CpuBudget b = *this;
    if (limited_) b.limit_ -= seconds;
    return b;
  }
  // Whichever of the two budgets ends first (both of this thread).
  CpuBudget earliest(const CpuBudget& other) const {
    if (!other.limited_) return *this;
    if (!limited_) return other;
    return limit_ <= other.limit_ ? *this : other;
  }

  bool limited() const { return limited_; }
  bool expired() const { return limited_ && thread_cpu_seconds() >= limit_; }
  // CPU seconds left (negative once spent; +inf when unlimited).
  double remaining_seconds() const {
    return limited_ ? limit_ - thread_cpu_seconds() : std::numeric_limits<double>::infinity();
  }

  // CPU time used by the calling thread since it started, in seconds.
  static double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }

 private:
  double limit_ = 0;
  bool limited_ = false;
};

}  // namespace wish
