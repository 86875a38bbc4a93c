#include "core/common/process_heap.hpp"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>

namespace wish {
namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr int kMmapThreshold = 32 << 20;  // glibc refuses more than HEAP_MAX_SIZE / 2 = 32 MiB on 64-bit
constexpr int kTrimThreshold = 1 << 30;
constexpr int kTopPad = 16 << 20;

std::uintptr_t align_up(std::uintptr_t p) { return (p + kHugePage - 1) & ~(kHugePage - 1); }
std::uintptr_t align_down(std::uintptr_t p) { return p & ~(kHugePage - 1); }

}  // namespace

HeapTuning tune_process_heap(std::size_t reserve_bytes) {
  HeapTuning out;
  out.thresholds_set = mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1 &&
                       mallopt(M_TRIM_THRESHOLD, kTrimThreshold) == 1 && mallopt(M_TOP_PAD, kTopPad) == 1;
  if (!out.thresholds_set) {
    out.note = "mallopt refused the thresholds (not glibc malloc?)";
    return out;
  }
  if (reserve_bytes == 0) return out;
  // Grow the brk heap by reserve_bytes in ONE step, touching only its first page: with the top pad at the reserve,
  // a request just larger than the heap's free top (mallinfo2's keepcost) makes malloc extend the heap by about the
  // pad. The range is advised before anything in it is written: a 2 MiB range with one 4 KiB page already faulted in
  // keeps a page table and stays on 4 KiB pages. The block is freed again into the heap's free top, which the trim
  // threshold keeps. A malloc that is not glibc's, or a heap that had to fall back to mmap, leaves brk unmoved.
  const auto brk_before = reinterpret_cast<std::uintptr_t>(sbrk(0));
  const std::size_t request = mallinfo2().keepcost + 4096;
  const int pad = static_cast<int>(std::min<std::size_t>(reserve_bytes, std::size_t{1} << 30));
  if (request >= static_cast<std::size_t>(kMmapThreshold) || mallopt(M_TOP_PAD, pad) != 1) {
    out.note = "the heap's free top is unexpectedly large: no huge-page advice";
    return out;
  }
  void* block = std::malloc(request);
  (void)mallopt(M_TOP_PAD, kTopPad);
  const auto brk_after = reinterpret_cast<std::uintptr_t>(sbrk(0));
  const auto block_at = reinterpret_cast<std::uintptr_t>(block);
  const bool from_brk = block && block_at >= brk_before - request && block_at + request <= brk_after;
  // The new free top starts just past the block (its header is written there): advise from the next 2 MiB boundary.
  const std::uintptr_t begin = align_up(block_at + request + 64), end = align_down(brk_after);
  std::free(block);
  if (!from_brk || brk_after <= brk_before) {
    out.note = "the heap did not grow by brk (another malloc, or brk unavailable): no huge-page advice";
    return out;
  }
  if (end <= begin) {
    out.note = "heap range smaller than one huge page";
    return out;
  }
  // A hint: without transparent huge page support madvise fails and the heap simply stays on 4 KiB pages.
  if (madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE) != 0) {
    out.note = "madvise(MADV_HUGEPAGE) refused (no transparent huge page support)";
    return out;
  }
  out.advised_begin = reinterpret_cast<const char*>(begin);
  out.advised_bytes = end - begin;
  return out;
}

}  // namespace wish
