#pragma once
// Which BLAS the process runs on, and its thread count. CHOLMOD's supernodal factorisation spends its time in
// BLAS (dsyrk/dgemm/dtrsm): Debian's reference libblas3 is ~15× slower than OpenBLAS, so benchmarks print this.
// The OpenBLAS entry points are looked up with dlsym(RTLD_DEFAULT) at run time, so the code links and runs with any
// BLAS (the functions then report "unknown" and do nothing).

#include <string>

namespace wish::linalg {

struct BlasInfo {
  std::string name;     // "OpenBLAS" or "unknown (not OpenBLAS)"
  std::string config;   // openblas_get_config(), e.g. "OpenBLAS 0.3.21 DYNAMIC_ARCH NO_AFFINITY Haswell MAX_THREADS=64"
  int threads = -1;     // openblas_get_num_threads(); -1 when unknown
  bool openblas = false;
};

BlasInfo blas_info();
// Sets the BLAS thread count (per worker: call with 1 when the caller parallelises over meshes). Returns false when
// the loaded BLAS offers no such call.
bool set_blas_threads(int threads);  // = wish::set_blas_thread_count (core/common/thread_policy.hpp)
// One line for logs: "OpenBLAS (OpenBLAS 0.3.21 ...), 1 thread(s)".
std::string describe_blas();

}  // namespace wish::linalg
