#pragma once
// Process signals for the service: SIGHUP reloads the models, SIGTERM / SIGINT start a graceful shutdown.
// The async handler only writes the signal number into a pipe; one watcher thread reads it and runs the callbacks
// as ordinary code (locks, logging, allocation are fine), never inside the signal handler.

#include <atomic>
#include <functional>
#include <thread>

namespace wish::server {

class SignalWatcher {
 public:
  // Installs the handlers for SIGHUP, SIGTERM and SIGINT (signals arriving before the watcher starts wait in the
  // pipe) and ignores SIGPIPE (a client that hangs up must not kill the server). Idempotent; call early.
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
