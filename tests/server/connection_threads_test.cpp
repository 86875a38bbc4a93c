// The on-demand connection threads (server/connection_threads.hpp): a task never waits behind busy ones below the
// cap; at the cap it waits for a thread; shutdown runs what is queued.

#include "server/connection_threads.hpp"

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include <gtest/gtest.h>

namespace wish::server {
namespace {

using namespace std::chrono_literals;

template <class F>
bool wait_for(F condition, std::chrono::milliseconds limit = 5000ms) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(2ms);
  }
  return condition();
}

TEST(ConnectionThreads, BusyTasksDoNotBlockANewOneBelowTheCap) {
  ConnectionThreads threads(0, 64);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<int> started{0};
  for (int i = 0; i < 40; ++i)  // 40 "idle clients" holding their threads
    threads.enqueue([&, released] { ++started; released.wait(); });
  ASSERT_TRUE(wait_for([&] { return started.load() == 40; }));
  std::promise<void> ran;
  threads.enqueue([&] { ran.set_value(); });  // "/healthz"
  EXPECT_EQ(ran.get_future().wait_for(2s), std::future_status::ready);
  EXPECT_EQ(threads.threads(), 41u);
  release.set_value();
  ASSERT_TRUE(wait_for([&] { return threads.busy() == 0; }));
  // Idle threads are reused: no new thread for the next task.
  std::promise<void> again;
  threads.enqueue([&] { again.set_value(); });
  EXPECT_EQ(again.get_future().wait_for(2s), std::future_status::ready);
  EXPECT_EQ(threads.threads(), 41u);
}

TEST(ConnectionThreads, AtTheCapATaskWaitsForAThread) {
  ConnectionThreads threads(0, 2);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<int> started{0};
  for (int i = 0; i < 2; ++i) threads.enqueue([&, released] { ++started; released.wait(); });
  ASSERT_TRUE(wait_for([&] { return started.load() == 2; }));
  std::atomic<bool> third{false};
  threads.enqueue([&] { third = true; });
  EXPECT_EQ(threads.waiting(), 1u);
  EXPECT_FALSE(third.load());
  EXPECT_EQ(threads.threads(), 2u);
  release.set_value();
  EXPECT_TRUE(wait_for([&] { return third.load(); }));
}

TEST(ConnectionThreads, WarmThreadsAreStartedAtOnceAndCapped) {
  ConnectionThreads threads(8, 4);
  EXPECT_EQ(threads.threads(), 4u);
  EXPECT_TRUE(wait_for([&] { return threads.busy() == 0; }));  // all idle, waiting for connections
}

TEST(ConnectionThreads, ShutdownRunsWhatIsQueued) {
  std::atomic<int> done{0};
  {
    ConnectionThreads threads(1, 1);
    for (int i = 0; i < 5; ++i)
      threads.enqueue([&] {
        std::this_thread::sleep_for(1ms);
        ++done;
      });
    threads.shutdown();
    EXPECT_EQ(done.load(), 5);
    threads.shutdown();  // idempotent
  }
  EXPECT_EQ(done.load(), 5);
}

}  // namespace
}  // namespace wish::server
