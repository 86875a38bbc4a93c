#pragma once
// Process signals for the service: SIGHUP reloads the models, SIGTERM / SIGINT start a graceful shutdown.
// The signals are blocked in every thread and taken synchronously by one watcher thread (sigtimedwait), so the
// callbacks run as ordinary code (locks, logging, allocation are fine) instead of in an async signal handler.

#include <atomic>
#include <functional>
#include <thread>

namespace wish::server {

class SignalWatcher {
 public:
  // Blocks SIGHUP, SIGTERM and SIGINT in the calling thread (threads started later inherit the mask) and ignores
  // SIGPIPE (a client that hangs up must not kill the server). Call before starting any thread.
  static void block_signals();

  SignalWatcher(std::function<void()> on_reload, std::function<void(int signal)> on_terminate);
  ~SignalWatcher();  // stops the watcher thread
  SignalWatcher(const SignalWatcher&) = delete;
  SignalWatcher& operator=(const SignalWatcher&) = delete;

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace wish::server
