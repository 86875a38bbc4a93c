#pragma once
// libsvm's messages (issue 25). libsvm 3.24 writes its optimisation progress through a process-global print hook
// (svm_set_print_string_function), but its "WARNING: reaching max number of iterations" — a pairwise solver that
// stopped at its iteration cap, max(10^7, 100 l), without converging — goes straight to fprintf(stderr). WISH
// never lets either reach the terminal raw; it counts the iteration-cap warnings of each svm_train call instead, so
// a training report can say how many fits did not converge.
// How: the print hook swallows the progress text, and the process's `stderr` FILE is replaced (once, for the
// process's lifetime) by an unbuffered stream that forwards everything to file descriptor 2 except that warning,
// which it counts. Both run on the thread that called svm_train, so the counting is per thread: a counter is
// active for the thread that created it, for the duration of its scope, and concurrent trainings on other threads
// never mix their counts. (std::cerr and direct writes to fd 2 are unaffected.)

namespace wish {

// Installs the hook and the stderr filter (once per process); idempotent.
void route_libsvm_messages();

// RAII: while alive, counts the iteration-cap warnings libsvm emits on this thread (one per pairwise solver that
// reached the cap). Nestable: the innermost counter of a thread counts.
class IterationCapCounter {
 public:
  IterationCapCounter();
  ~IterationCapCounter();
  IterationCapCounter(const IterationCapCounter&) = delete;
  IterationCapCounter& operator=(const IterationCapCounter&) = delete;
  int warnings() const { return warnings_; }
  void add_warning() { ++warnings_; }

 private:
  int warnings_ = 0;
  IterationCapCounter* outer_ = nullptr;
};

}  // namespace wish
