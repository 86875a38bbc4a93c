#include "core/common/thread_policy.hpp"

#include <dlfcn.h>
#include <omp.h>

namespace wish {

bool set_blas_thread_count(int threads) {
  using SetThreads = void (*)(int);
  const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (!set) return false;
  set(threads < 1 ? 1 : threads);
  return true;
}

bool stop_blas_threads() {
  // OpenBLAS's own shutdown of its thread server (what it runs at fork and at exit): joins the helper threads.
  // openblas_set_num_threads and a threaded BLAS call start them again (blas_server.c: goto_set_num_threads,
  // exec_blas); with one thread set, BLAS calls run on the caller and start none.
  using Shutdown = int (*)();
  const auto shutdown = reinterpret_cast<Shutdown>(dlsym(RTLD_DEFAULT, "blas_thread_shutdown_"));
  if (!shutdown) return false;
  return shutdown() == 0;
}

void limit_compute_threads_to_one() {
  omp_set_num_threads(1);
  omp_set_dynamic(0);
  (void)set_blas_thread_count(1);  // false when the BLAS is not OpenBLAS: nothing to limit then
}

}  // namespace wish
