#include "server/listener.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

#include <spdlog/spdlog.h>

namespace wish::server {

Listener::Listener(int listening_socket) : fd_(listening_socket) {
  // Non-blocking: accept() after a poll() wake-up, or while taking the queue at the stop, must never wait.
  const int flags = ::fcntl(fd_, F_GETFL, 0);
  if (flags >= 0) ::fcntl(fd_, F_SETFL, flags | O_NONBLOCK);
}

Listener::~Listener() {
  if (fd_ >= 0) ::close(fd_);
}

bool Listener::accept_one(const std::function<void(int)>& on_accept) {
  for (;;) {
    // The accepted socket is blocking (Linux does not inherit O_NONBLOCK): the connection code waits with poll().
    const int sock = ::accept4(fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (sock >= 0) {
      on_accept(sock);
      return true;
    }
    switch (errno) {
      case EINTR:
      case ECONNABORTED:  // the client gave up before we took it: the next one may be there
        continue;
      case EAGAIN:
        return false;
      case EMFILE:
      case ENFILE:
        // Out of descriptors: the connection stays queued; wait a moment for a connection to close (a busy loop
        // otherwise, as poll() keeps reporting it).
        spdlog::warn("accept: {} (connections wait in the kernel's queue)", std::strerror(errno));
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        return false;
      default:
        spdlog::error("accept: {}", std::strerror(errno));
        return false;
    }
  }
}

void Listener::run(const std::function<void(int)>& on_accept) {
  if (fd_ < 0) return;
  pollfd fds[2] = {{fd_, POLLIN, 0}, {stop_.fd(), POLLIN, 0}};
  while (!stop_.is_set()) {
    const int n = ::poll(fds, 2, -1);
    if (n < 0) {
      if (errno == EINTR) continue;
      spdlog::error("poll on the listening socket: {}", std::strerror(errno));
      break;
    }
    if (fds[1].revents != 0) break;
    if (fds[0].revents & POLLIN)
      while (!stop_.is_set() && accept_one(on_accept)) {
      }
  }
  // Stopped: every connection the kernel completed before this point was accepted on the client's side too.
  std::size_t taken = 0;
  while (accept_one(on_accept)) ++taken;
  ::close(fd_);
  fd_ = -1;
  if (taken > 0) spdlog::info("listener closed; {} connection(s) still queued in the kernel were taken", taken);
}

}  // namespace wish::server
