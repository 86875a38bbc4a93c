#include "core/common/process_signals.hpp"

#include <pthread.h>

#include <csignal>
#include <initializer_list>

namespace wish {

namespace {
sigset_t process_signals() {
  sigset_t set;
  sigemptyset(&set);
  for (int sig : {SIGHUP, SIGTERM, SIGINT}) sigaddset(&set, sig);
  return set;
}

// Runs from the executable's .preinit_array: before any shared library's initialiser, hence before any thread.
// Only the (single) main thread exists, so sigprocmask is exact here.
void block_before_library_constructors(int, char**, char**) {
  const sigset_t set = process_signals();
  sigprocmask(SIG_BLOCK, &set, nullptr);
}

[[gnu::section(".preinit_array"), gnu::used]] void (*const preinit_block_signals)(int, char**, char**) =
    &block_before_library_constructors;
}  // namespace

void unblock_process_signals() {
  const sigset_t set = process_signals();
  pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
}

bool process_signals_blocked() {
  sigset_t current;
  pthread_sigmask(SIG_BLOCK, nullptr, &current);
  for (int sig : {SIGHUP, SIGTERM, SIGINT})
    if (sigismember(&current, sig) != 1) return false;
  return true;
}

}  // namespace wish
