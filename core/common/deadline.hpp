#pragma once
// A per-request time limit and cancellation flag, checked by long computations between steps
// (e.g. between Willmore flow steps). Default-constructed: no limit, never cancelled.

#include <atomic>
#include <chrono>
#include <memory>
#include <string>

#include "core/common/errors.hpp"

namespace wish {

class Deadline {
 public:
  using Clock = std::chrono::steady_clock;

  Deadline() = default;  // unlimited
  static Deadline after(std::chrono::duration<double> budget) {
    Deadline d;
    d.limit_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(budget);
    d.limited_ = true;
    return d;
  }

  // Shared flag another thread may set (e.g. on shutdown) to stop the computation early.
  void attach_cancel_flag(std::shared_ptr<std::atomic<bool>> flag) { cancel_ = std::move(flag); }

  bool expired() const {
    if (cancel_ && cancel_->load(std::memory_order_relaxed)) return true;
    return limited_ && Clock::now() >= limit_;
  }

  // Throws TimeoutError naming the stage when the limit has passed or the request was cancelled.
  void check(const char* stage) const {
    if (!expired()) return;
    if (cancel_ && cancel_->load(std::memory_order_relaxed))
      throw WishError(ErrorCategory::Unavailable, "cancelled", std::string("request cancelled during ") + stage);
    throw TimeoutError(std::string("time limit exceeded during ") + stage, {{"stage", std::string(stage)}});
  }

 private:
  Clock::time_point limit_{};
  bool limited_ = false;
  std::shared_ptr<std::atomic<bool>> cancel_;
};

}  // namespace wish
