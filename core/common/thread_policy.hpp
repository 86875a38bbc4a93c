#pragma once
// The one thread policy of WISH: when work is parallel over meshes (training, the service's worker pool, batch
// runs), each worker computes on one thread. Letting every worker also fan out over OpenMP (geometry, SH fit) and
// OpenBLAS threads (CHOLMOD's supernodal BLAS) oversubscribes the cores: measured on 2 cores, sys time ~ user time
// from spinning OpenBLAS threads, and latency under load became erratic.
// The OpenBLAS entry point is looked up with dlsym(RTLD_DEFAULT) at run time, so the code links and runs with any
// BLAS (the setter then reports false and does nothing).

namespace wish {

// Sets the BLAS thread count (process-wide for OpenBLAS; at least 1). Returns false when the loaded BLAS offers no
// such call.
bool set_blas_thread_count(int threads);

// Stops the BLAS's helper threads (OpenBLAS starts one per core in its library constructor, before main, and each
// spins in sched_yield for a while before it sleeps: 5 % of a nucleus map's CPU on 2 cores). A later call that
// sets a thread count (any, 1 included) starts them again: set the count first. Returns false when the loaded BLAS
// offers no such call (not OpenBLAS).
bool stop_blas_threads();

// omp_set_num_threads(1) and omp_set_dynamic(0) for the calling thread (OpenMP's nthreads-var is per thread, so
// call it at the start of each worker) and the BLAS thread count to 1 (process-wide, which a worker pool wants).
void limit_compute_threads_to_one();

}  // namespace wish
