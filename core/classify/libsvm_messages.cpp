#include "core/classify/libsvm_messages.hpp"

#include <svm.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <mutex>

namespace wish {
namespace {

thread_local IterationCapCounter* active_counter = nullptr;
constexpr char kCapWarning[] = "reaching max number of iterations";

bool is_cap_warning(const char* text, std::size_t size) {
  return memmem(text, size, kCapWarning, sizeof kCapWarning - 1) != nullptr;
}

// The print hook: progress dots, "*", "optimization finished, #iter = ..." — nothing a report needs.
void swallow_progress(const char*) {}

// The stderr filter's write function: the cap warning is counted on the calling thread (or dropped when no counter
// is active), everything else goes to fd 2 unchanged. An unbuffered FILE hands each fprintf over in one call.
ssize_t filter_stderr(void*, const char* buf, std::size_t size) {
  if (is_cap_warning(buf, size)) {
    if (active_counter) active_counter->add_warning();
    return static_cast<ssize_t>(size);
  }
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(STDERR_FILENO, buf + done, size - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return done ? static_cast<ssize_t>(done) : -1;
    }
    done += static_cast<std::size_t>(n);
  }
  return static_cast<ssize_t>(size);
}

}  // namespace

void route_libsvm_messages() {
  static std::once_flag once;
  std::call_once(once, [] {
    svm_set_print_string_function(&swallow_progress);
    cookie_io_functions_t io{};
    io.write = &filter_stderr;
    if (FILE* filtered = fopencookie(nullptr, "w", io)) {
      setvbuf(filtered, nullptr, _IONBF, 0);
      std::fflush(stderr);
      stderr = filtered;  // glibc: `stderr` is an assignable FILE*; libsvm reads it at each fprintf
    }
  });
}

IterationCapCounter::IterationCapCounter() : outer_(active_counter) {
  route_libsvm_messages();
  active_counter = this;
}

IterationCapCounter::~IterationCapCounter() { active_counter = outer_; }

}  // namespace wish
