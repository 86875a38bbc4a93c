#include "server/thread_limits.hpp"

#include <omp.h>

#include "core/linalg/blas_info.hpp"

namespace wish::server {

void limit_compute_threads_to_one() {
  omp_set_num_threads(1);  // OpenMP's nthreads-var is per thread: affects parallel regions started by this worker
  omp_set_dynamic(0);
  (void)wish::linalg::set_blas_threads(1);  // false when the BLAS is not OpenBLAS: nothing to limit then
}

}  // namespace wish::server
