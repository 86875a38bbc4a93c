#pragma once
// A one-way flag that a thread blocked in poll() can watch beside its socket: set() makes fd() readable for good
// (an eventfd that is written once and never read). The shutdown phases use it (http_server.cpp): a connection
// waiting for its next request, a body upload waiting for bytes and the accept loop all wake at once, without
// polling in slices.

#include <atomic>

namespace wish::server {

class WakeLatch {
 public:
  WakeLatch();  // throws std::system_error when no eventfd can be made
  ~WakeLatch();
  WakeLatch(const WakeLatch&) = delete;
  WakeLatch& operator=(const WakeLatch&) = delete;

  void set();  // idempotent, thread-safe
  bool is_set() const { return set_.load(); }
  int fd() const { return fd_; }

 private:
  int fd_ = -1;
  std::atomic<bool> set_{false};
};

}  // namespace wish::server
