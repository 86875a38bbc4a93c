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

void limit_compute_threads_to_one() {
  omp_set_num_threads(1);
  omp_set_dynamic(0);
  (void)set_blas_thread_count(1);  // false when the BLAS is not OpenBLAS: nothing to limit then
}

}  // namespace wish
