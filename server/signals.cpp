#include "server/signals.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <stdexcept>

#include <spdlog/spdlog.h>

namespace wish::server {

namespace {
// Self-pipe: the async handler only write()s the signal number (async-signal-safe); the watcher thread reads it.
// Blocking the signals with pthread_sigmask is not enough: libraries start threads before main (OpenBLAS's pool),
// and a signal delivered to one of those would take the default action and kill the process.
int g_pipe[2] = {-1, -1};

extern "C" void on_signal(int sig) {
  const int saved = errno;
  const unsigned char byte = static_cast<unsigned char>(sig);
  [[maybe_unused]] const auto n = write(g_pipe[1], &byte, 1);
  errno = saved;
}
}  // namespace

void SignalWatcher::block_signals() {
  std::signal(SIGPIPE, SIG_IGN);  // a client that hangs up must not kill the server
  if (g_pipe[0] >= 0) return;
  if (pipe2(g_pipe, O_CLOEXEC | O_NONBLOCK) != 0) throw std::runtime_error("cannot create the signal pipe");
  struct sigaction action;
  std::memset(&action, 0, sizeof action);
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  for (int sig : {SIGHUP, SIGTERM, SIGINT}) sigaction(sig, &action, nullptr);
}

SignalWatcher::SignalWatcher(std::function<void()> on_reload, std::function<void(int)> on_terminate) {
  block_signals();
  thread_ = std::thread([this, on_reload = std::move(on_reload), on_terminate = std::move(on_terminate)] {
    bool terminating = false;
    while (!stop_.load()) {
      pollfd fd{g_pipe[0], POLLIN, 0};
      if (poll(&fd, 1, 200) <= 0) continue;  // timeout (to notice stop_) or EINTR
      unsigned char byte = 0;
      while (read(g_pipe[0], &byte, 1) == 1) {
        const int sig = byte;
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
    }
  });
}

SignalWatcher::~SignalWatcher() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

}  // namespace wish::server
