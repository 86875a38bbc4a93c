#pragma once
// Process signals for the service: SIGHUP reloads the models, SIGTERM / SIGINT start a graceful shutdown.
//
// No signal handler is ever installed for them. SIGHUP, SIGTERM and SIGINT are blocked in every thread (the `wish`
// executable blocks them before any library constructor can start a thread, see core/common/process_signals.cpp) and one watcher
// thread takes them synchronously with sigtimedwait, then runs the callbacks as ordinary code. This makes the
// service immune to libraries that swap process-wide handlers: GKlib (libmetis, called by CHOLMOD for every
// ordering) installs `gk_sigthrow` for SIGTERM around each METIS call with signal() and restores the previous
// handler afterwards; the save/restore is per thread but the handler is per process, so two workers ordering at
// once can leave `gk_sigthrow` installed, and a later SIGTERM delivered to a thread outside METIS longjmps through
// an unset jump buffer (gk_cur_jbufs == -1): SIGSEGV. A blocked signal never reaches any handler.

#include <atomic>
#include <functional>
#include <thread>

namespace wish::server {

class SignalWatcher {
 public:
  // Blocks SIGHUP, SIGTERM and SIGINT in the calling thread (threads created afterwards inherit the mask; signals
  // arriving before the watcher starts stay pending) and ignores SIGPIPE (a client that hangs up must not kill the
  // server). Idempotent; call before any thread is created.
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
