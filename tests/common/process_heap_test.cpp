// tune_process_heap (core/common/process_heap.hpp): the brk heap grows by the reserve in one step, the grown range
// is advised MADV_HUGEPAGE (the kernel's own record of it, /proc/self/smaps VmFlags "hg", is read back), later
// allocations are served from it, and freed memory stays in the process instead of being trimmed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "core/common/process_heap.hpp"

namespace {

// The VmFlags line of the /proc/self/smaps mapping that contains `address` ("" when none does).
std::string vm_flags_of(const void* address) {
  const auto a = reinterpret_cast<std::uintptr_t>(address);
  std::ifstream smaps("/proc/self/smaps");
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> lo >> dash >> hi && dash == '-' && line.find(':') > line.find(' ')) {
      inside = lo <= a && a < hi;
      continue;
    }
    if (inside && line.rfind("VmFlags:", 0) == 0) return line;
  }
  return "";
}

bool has_flag(const std::string& vm_flags, const std::string& flag) {
  std::istringstream words(vm_flags);
  for (std::string w; words >> w;)
    if (w == flag) return true;
  return false;
}

TEST(ProcessHeap, ReserveIsAdvisedHugeAndServesLaterAllocations) {
  constexpr std::size_t kReserve = std::size_t{64} << 20;
  const wish::HeapTuning t = wish::tune_process_heap(kReserve);
  if (!t.thresholds_set) GTEST_SKIP() << "not glibc malloc (e.g. a sanitizer's allocator): " << t.note;
  if (t.advised_bytes == 0) GTEST_SKIP() << "no huge-page advice on this system: " << t.note;
  EXPECT_TRUE(t.note.empty()) << t.note;
  const auto begin = reinterpret_cast<std::uintptr_t>(t.advised_begin);
  EXPECT_EQ(begin % (std::size_t{2} << 20), 0u);
  EXPECT_EQ(t.advised_bytes % (std::size_t{2} << 20), 0u);
  // The pad, less the partial huge pages at its two ends.
  EXPECT_GE(t.advised_bytes, kReserve - (std::size_t{4} << 20));
  EXPECT_LE(begin + t.advised_bytes, reinterpret_cast<std::uintptr_t>(sbrk(0)));
  EXPECT_TRUE(has_flag(vm_flags_of(t.advised_begin), "hg")) << vm_flags_of(t.advised_begin);

  // A 24 MiB block (below the 32 MiB mmap threshold) comes from the heap, i.e. from the advised range, without
  // growing it; written and freed, it stays in the process (the trim threshold) and is reused by the next one.
  const void* brk_before = sbrk(0);
  constexpr std::size_t kBlock = std::size_t{24} << 20;
  char* block = static_cast<char*>(std::malloc(kBlock));
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kBlock);
  const auto at = reinterpret_cast<std::uintptr_t>(block);
  EXPECT_GE(at + kBlock, begin);
  EXPECT_LE(at + kBlock, begin + t.advised_bytes);
  EXPECT_EQ(sbrk(0), brk_before);
  std::free(block);
  EXPECT_EQ(sbrk(0), brk_before) << "freed memory was trimmed";
  void* again = std::malloc(kBlock);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(again), at);
  std::free(again);
}

TEST(ProcessHeap, ZeroReserveSetsOnlyTheThresholds) {
  const void* brk_before = sbrk(0);
  const wish::HeapTuning t = wish::tune_process_heap(0);
  if (!t.thresholds_set) GTEST_SKIP() << "not glibc malloc: " << t.note;
  EXPECT_EQ(t.advised_begin, nullptr);
  EXPECT_EQ(t.advised_bytes, 0u);
  EXPECT_EQ(sbrk(0), brk_before);
}

}  // namespace
