#include "server/signals.hpp"

#include <pthread.h>

#include <cerrno>
#include <csignal>
#include <initializer_list>
#include <ctime>

#include <spdlog/spdlog.h>

namespace wish::server {

namespace {
sigset_t service_signals() {
  sigset_t set;
  sigemptyset(&set);
  for (int sig : {SIGHUP, SIGTERM, SIGINT}) sigaddset(&set, sig);
  return set;
}
}  // namespace

void SignalWatcher::block_signals() {
  std::signal(SIGPIPE, SIG_IGN);  // a client that hangs up must not kill the server
  const sigset_t set = service_signals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

SignalWatcher::SignalWatcher(std::function<void()> on_reload, std::function<void(int)> on_terminate) {
  block_signals();
  thread_ = std::thread([this, on_reload = std::move(on_reload), on_terminate = std::move(on_terminate)] {
    const sigset_t set = service_signals();
    const timespec poll_interval{0, 200'000'000};  // to notice stop_
    bool terminating = false;
    while (!stop_.load()) {
      const int sig = sigtimedwait(&set, nullptr, &poll_interval);
      if (sig < 0) continue;  // EAGAIN (timeout) or EINTR
      if (sig == SIGHUP) {
        spdlog::info("SIGHUP: reloading models");
        on_reload();
      } else if (!terminating) {
        terminating = true;  // a second SIGTERM during the grace period changes nothing
        on_terminate(sig);
      } else {
        spdlog::warn("signal {} again: shutdown already in progress", sig);
      }
    }
  });
}

SignalWatcher::~SignalWatcher() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

}  // namespace wish::server
