#include "core/linalg/serial_openmp.hpp"

#include <dlfcn.h>
#include <omp.h>

#include <cstdio>
#include <cstdlib>

namespace wish::linalg {
namespace {

thread_local int serial_scope_depth = 0;

using GompParallelFn = void (*)(void (*)(void*), void*, unsigned, unsigned);

// libgomp's own GOMP_parallel (the next definition after this one in the lookup order).
GompParallelFn libgomp_parallel() {
  static const GompParallelFn next = [] {
    const auto fn = reinterpret_cast<GompParallelFn>(dlsym(RTLD_NEXT, "GOMP_parallel"));
    if (!fn) {
      std::fprintf(stderr, "wish: libgomp's GOMP_parallel not found (%s)\n", dlerror());
      std::abort();
    }
    return fn;
  }();
  return next;
}

}  // namespace

SerialOpenMpScope::SerialOpenMpScope() : dynamic_(omp_get_dynamic()), threads_(omp_get_max_threads()) {
  omp_set_dynamic(1);
  omp_set_num_threads(1);
  ++serial_scope_depth;
}

SerialOpenMpScope::~SerialOpenMpScope() {
  --serial_scope_depth;
  omp_set_num_threads(threads_);
  omp_set_dynamic(dynamic_);
}

bool SerialOpenMpScope::active() { return serial_scope_depth > 0; }

}  // namespace wish::linalg

// GCC's entry point for `#pragma omp parallel` (libgomp ABI GOMP_4.0): see serial_openmp.hpp.
extern "C" __attribute__((visibility("default"))) void GOMP_parallel(void (*fn)(void*), void* data, unsigned num_threads,
                                                                     unsigned flags) {
  if (wish::linalg::SerialOpenMpScope::active() && omp_get_level() == 0) {
    fn(data);
    return;
  }
  wish::linalg::libgomp_parallel()(fn, data, num_threads, flags);
}
