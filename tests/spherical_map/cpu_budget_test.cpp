// CpuBudget (core/common/cpu_budget.hpp): the soft flow budget of the map chain counts the calling thread's CPU
// time, so sleeping (or being descheduled on a loaded machine) does not spend it and computing does.
#include <chrono>
#include <cmath>
#include <thread>

#include <gtest/gtest.h>

#include "core/common/cpu_budget.hpp"

namespace wish {
namespace {

TEST(CpuBudget, DefaultIsUnlimited) {
  const CpuBudget b;
  EXPECT_FALSE(b.limited());
  EXPECT_FALSE(b.expired());
  EXPECT_TRUE(std::isinf(b.remaining_seconds()));
}

TEST(CpuBudget, SleepingDoesNotSpendIt) {
  const CpuBudget b = CpuBudget::for_this_thread(std::chrono::milliseconds(100));
  const auto t0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  // The wall clock has moved on past the budget ...
  ASSERT_GE(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(200));
  // ... but the thread used (almost) no CPU while asleep.
  EXPECT_FALSE(b.expired());
  EXPECT_GT(b.remaining_seconds(), 0.05);
}

TEST(CpuBudget, ComputingSpendsIt) {
  // `start` is read before the budget is made, so the budget's clock starts no earlier than `start` and expiry
  // implies used >= 50 ms exactly (read after, the two reads' gap made used fall a few ns short: CI, 0.0499996).
  const double start = CpuBudget::thread_cpu_seconds();
  const CpuBudget b = CpuBudget::for_this_thread(std::chrono::milliseconds(50));
  // Work until the budget reports expiry; bounded (10 s of CPU would mean the clock does not advance).
  volatile double sink = 0;
  long rounds = 0;
  while (!b.expired() && CpuBudget::thread_cpu_seconds() - start < 10.0) {
    for (int i = 0; i < 10000; ++i) sink = sink + std::sqrt(static_cast<double>(i + rounds));
    ++rounds;
  }
  const double used = CpuBudget::thread_cpu_seconds() - start;
  EXPECT_TRUE(b.expired());
  EXPECT_GE(used, 0.05);
  EXPECT_LT(used, 1.0);  // expiry is reported promptly once the budget is spent
  EXPECT_LE(b.remaining_seconds(), 0.0);
}

TEST(CpuBudget, AnotherThreadsWorkIsNotCounted) {
  const CpuBudget b = CpuBudget::for_this_thread(std::chrono::milliseconds(100));
  std::thread worker([] {
    const double start = CpuBudget::thread_cpu_seconds();
    volatile double sink = 0;
    while (CpuBudget::thread_cpu_seconds() - start < 0.3)
      for (int i = 0; i < 10000; ++i) sink = sink + std::sqrt(static_cast<double>(i));
  });
  worker.join();
  EXPECT_FALSE(b.expired());
}

TEST(CpuBudget, AReserveEndsTheSameClockEarlierAndEarliestPicksTheTighterBudget) {
  const CpuBudget b = CpuBudget::for_this_thread(std::chrono::seconds(100));
  // Remaining time of two budgets read at (almost) the same instant differs by the reserve.
  const CpuBudget r = b.with_reserve(30);
  EXPECT_NEAR(b.remaining_seconds() - r.remaining_seconds(), 30, 1e-3);
  EXPECT_TRUE(b.with_reserve(1000).expired());  // a reserve larger than the budget: spent already
  EXPECT_FALSE(CpuBudget{}.with_reserve(1000).limited());  // unlimited stays unlimited
  EXPECT_NEAR(b.earliest(r).remaining_seconds(), r.remaining_seconds(), 1e-3);
  EXPECT_NEAR(r.earliest(b).remaining_seconds(), r.remaining_seconds(), 1e-3);
  EXPECT_NEAR(CpuBudget{}.earliest(r).remaining_seconds(), r.remaining_seconds(), 1e-3);
  EXPECT_NEAR(r.earliest(CpuBudget{}).remaining_seconds(), r.remaining_seconds(), 1e-3);
}

}  // namespace
}  // namespace wish
