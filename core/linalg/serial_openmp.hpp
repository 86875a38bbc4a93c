#pragma once
// Runs the OpenMP parallel regions of a library call (CHOLMOD's) as plain serial code on the calling thread, without
// entering the OpenMP runtime (issue 28: where a nucleus map's time went).
//
// CHOLMOD 3 (SuiteSparse 5) wraps its supernodal scatter / clear / copy loops in `omp parallel for
// num_threads(4) if (size > threshold)`: 15–20 thousand regions per complex Dirac factorisation of a 10.8K-vertex
// nucleus. GCC calls GOMP_parallel for every one of them, also when the `if` is false (a team of one), and libgomp
// ends each team with an unconditional futex wake of its barrier — one system call per region — and, with dyn-var on
// (which the previous guard used to stop the 4-thread clause), also reads the load average and the affinity mask
// (two more system calls) per region whose `if` is true. Measured on nucleus-1 (`strace -c`, `perf`): 102,280 futex
// calls per `wish map`, a quarter of the process's CPU time in the kernel; running the regions inline cut the
// process's CPU time by 20 % (paired whole-process runs, the same bypass preloaded into the old binary: A/B cpu
// 0.80), with a bitwise-identical map (docs/benchmarks.md).
//
// How: this library defines GOMP_parallel (libgomp's entry point for a parallel region, GCC's ABI since GCC 4.9), so
// the dynamic linker binds CHOLMOD's and our own calls to it ahead of libgomp's. While a SerialOpenMpScope is alive
// on the calling thread and no parallel region encloses it (omp_get_level() == 0), the region's body is called
// directly: outside a team, omp_get_num_threads() is 1 and omp_get_thread_num() 0, so a static loop covers all its
// iterations, and libgomp runs orphaned work-sharing constructs (dynamic loops, single, barriers) on one thread
// (OpenMP 5.2 §2.9 "orphaned constructs"). Everything else — other threads, nested calls, no scope — goes to
// libgomp's GOMP_parallel unchanged. The scope also sets the thread's OpenMP ICVs to one thread (dyn-var on,
// nthreads-var 1) and restores them, for the nested case that does reach libgomp.

namespace wish::linalg {

class SerialOpenMpScope {
 public:
  SerialOpenMpScope();
  ~SerialOpenMpScope();
  SerialOpenMpScope(const SerialOpenMpScope&) = delete;
  SerialOpenMpScope& operator=(const SerialOpenMpScope&) = delete;

  // True while a scope is alive on the calling thread (for tests).
  static bool active();

 private:
  int dynamic_;
  int threads_;
};

}  // namespace wish::linalg
