#pragma once
// The cancel flags of the compute requests in flight. Each request registers one flag (attached to the deadline of
// each of its jobs) for as long as it waits; past the shutdown grace period run_server cancels them all, and the
// pipeline stops at its next deadline check (503 "cancelled").

#include <atomic>
#include <cstddef>
#include <memory>
#include <mutex>
#include <set>

namespace wish::server {

class CancelRegistry {
 public:
  using Flag = std::shared_ptr<std::atomic<bool>>;

  // Registered while the returned token lives.
  class Registration {
   public:
    Registration(CancelRegistry& registry, Flag flag);
    ~Registration();
    Registration(const Registration&) = delete;
    Registration& operator=(const Registration&) = delete;

   private:
    CancelRegistry& registry_;
    Flag flag_;
  };

  // Cancels every registered flag and every one registered later: a request that was between its admission and
  // its registration when the grace period ran out would otherwise compute to the end and hold up the exit.
  void cancel_all();
  std::size_t size() const;

 private:
  friend class Registration;
  mutable std::mutex mutex_;
  std::set<Flag> flags_;
  bool cancelled_all_ = false;
};

}  // namespace wish::server
