#include "server/signals.hpp"

#include <csignal>
#include <ctime>

#include <spdlog/spdlog.h>

namespace wish::server {

namespace {
sigset_t watched_set() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGHUP);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGINT);
  return set;
}
}  // namespace

void SignalWatcher::block_signals() {
  const sigset_t set = watched_set();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
}

SignalWatcher::SignalWatcher(std::function<void()> on_reload, std::function<void(int)> on_terminate) {
  thread_ = std::thread([this, on_reload = std::move(on_reload), on_terminate = std::move(on_terminate)] {
    const sigset_t set = watched_set();
    const timespec poll{0, 200'000'000};  // wake up to notice stop_
    bool terminating = false;
    while (!stop_.load()) {
      const int sig = sigtimedwait(&set, nullptr, &poll);
      if (sig < 0) continue;  // timeout or EINTR
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
