#include "server/wake_latch.hpp"

#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <system_error>

namespace wish::server {

WakeLatch::WakeLatch() : fd_(::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {
  if (fd_ < 0) throw std::system_error(errno, std::generic_category(), "eventfd");
}

WakeLatch::~WakeLatch() { ::close(fd_); }

void WakeLatch::set() {
  if (set_.exchange(true)) return;
  const std::uint64_t one = 1;
  // Cannot fail for an eventfd counter far below its maximum; the flag above is what readers trust anyway.
  [[maybe_unused]] const ssize_t n = ::write(fd_, &one, sizeof one);
}

}  // namespace wish::server
