#pragma once
// The malloc heap of a compute process, set up once at start-up so that a map's working memory is faulted in a few
// 2 MiB pages at a time and reused, not faulted in 4 KiB at a time and handed back to the kernel.
//
// Why: on the virtual machines WISH runs on, a page fault is expensive. Measured on the shared 2-core development
// VM (a paravirtualised guest): writing 28 MiB of fresh 4 KiB pages cost 123 ms of CPU (15 µs a fault), the same on
// transparent huge pages 3–8 ms. `wish map` of a 10.8K-vertex nucleus faulted 8,750 times (~35 MiB of 4 KiB
// pages: Eigen matrices, the operators, CHOLMOD's workspace), a fifth of its CPU time. glibc can do this itself
// (GLIBC_TUNABLES=glibc.malloc.hugetlb=1 with a large top pad and trim threshold: 1,140 faults), but only from the
// environment at process start; this does the equivalent from main().
//
// What tune_process_heap() does (glibc malloc; mallopt(3), madvise(2)):
//  * M_MMAP_THRESHOLD 32 MiB (glibc's largest): blocks up to 32 MiB come from the heap and their memory is reused
//    after free() instead of being unmapped and faulted in again by the next allocation of that size;
//  * M_TRIM_THRESHOLD 1 GiB and M_TOP_PAD 16 MiB: freed memory stays in the process (its peak is what it keeps), and
//    the heap grows in steps of at least 16 MiB;
//  * the heap is grown once by `reserve_bytes` (address space only: nothing is touched) and that range is advised
//    MADV_HUGEPAGE, so the kernel backs it with 2 MiB pages when transparent huge pages are enabled in `madvise` or
//    `always` mode (Debian's default is `madvise`). Memory cost: the resident size rounds up to 2 MiB steps within
//    the range.
// Call it once, from the main thread, before the work starts (other threads' arenas are not affected: they are not
// the brk heap). Safe under any malloc: each step that does not apply is skipped and reported, never fatal.

#include <cstddef>
#include <string>

namespace wish {

struct HeapTuning {
  bool thresholds_set = false;  // mallopt accepted the mmap / trim thresholds and the top pad
  // The range advised MADV_HUGEPAGE (2 MiB-aligned, inside the brk heap), empty when none was.
  const char* advised_begin = nullptr;
  std::size_t advised_bytes = 0;
  std::string note;  // why a step was skipped (empty when all applied)
};

inline constexpr std::size_t kDefaultHeapReserve = std::size_t{128} << 20;

HeapTuning tune_process_heap(std::size_t reserve_bytes = kDefaultHeapReserve);

}  // namespace wish
