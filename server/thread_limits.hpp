#pragma once
// One compute thread per worker: the pool already runs `workers` meshes in parallel, so letting each of them also
// fan out over OpenMP (geometry, SH fit) and OpenBLAS threads (CHOLMOD) would oversubscribe the cores and make
// latency erratic under load.

namespace wish::server {

// Sets omp_set_num_threads(1) for the calling thread and the BLAS thread count to 1 (OpenBLAS's setting is
// process-wide, which is what we want for a server anyway). Call at the start of each worker thread.
void limit_compute_threads_to_one();

}  // namespace wish::server
