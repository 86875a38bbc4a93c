// The work backlog (server/work_backlog.hpp): what it predicts from the jobs it learned, and the wait it predicts
// for a job admitted now (the workers taken first in, first out).

#include "server/work_backlog.hpp"

#include <cmath>
#include <cstdint>
#include <memory>

#include <gtest/gtest.h>

namespace wish::server {
namespace {

// With the rate learned at 1 s per MB^1.25, the bytes of a job predicted at `seconds`.
std::uint64_t bytes_for(double seconds) { return static_cast<std::uint64_t>(std::llround(1e6 * std::pow(seconds, 0.8))); }

std::shared_ptr<WorkBacklog> backlog_at_one_second_per_megabyte(int workers) {
  auto backlog = std::make_shared<WorkBacklog>(workers);
  backlog->learn(1'000'000, 1.0);
  return backlog;
}

TEST(WorkBacklog, PredictsNothingBeforeAJobCompleted) {
  auto backlog = std::make_shared<WorkBacklog>(2);
  EXPECT_FALSE(backlog->predict(1'000'000).has_value());
  EXPECT_EQ(backlog->wait_seconds(), 0.0);
}

TEST(WorkBacklog, PredictionGrowsAsMegabytesToThePower1_25) {
  auto backlog = std::make_shared<WorkBacklog>(1);
  backlog->learn(1'000'000, 2.0);
  EXPECT_NEAR(*backlog->predict(1'000'000), 2.0, 1e-12);
  EXPECT_NEAR(*backlog->predict(16'000'000), 2.0 * 32.0, 1e-9);  // 16^1.25 = 32
}

TEST(WorkBacklog, LearnedRateFollowsTheNewestJobs) {
  auto backlog = std::make_shared<WorkBacklog>(1);
  backlog->learn(1'000'000, 2.0);
  for (int i = 0; i < 20; ++i) backlog->learn(1'000'000, 4.0);  // the machine slowed down
  EXPECT_NEAR(*backlog->predict(1'000'000), 4.0, 0.01);
  backlog->learn(1'000'000, 0.0);  // not a measurement: ignored
  backlog->learn(1'000'000, std::nan(""));
  EXPECT_NEAR(*backlog->predict(1'000'000), 4.0, 0.01);
}

TEST(WorkBacklog, NoWaitWhileAWorkerIsFree) {
  auto backlog = backlog_at_one_second_per_megabyte(2);
  auto running = backlog->enter(bytes_for(10.0));
  running->start();
  EXPECT_EQ(backlog->wait_seconds(), 0.0);
}

TEST(WorkBacklog, WaitingJobsTakeTheFirstFreeWorkerInTurn) {
  auto backlog = backlog_at_one_second_per_megabyte(2);
  auto a = backlog->enter(bytes_for(10.0));
  auto b = backlog->enter(bytes_for(6.0));
  a->start();
  b->start();
  EXPECT_NEAR(backlog->wait_seconds(), 6.0, 0.5);   // b's worker is free first
  auto c = backlog->enter(bytes_for(8.0));          // waits for b's worker: free again at 14
  EXPECT_NEAR(backlog->wait_seconds(), 10.0, 0.5);  // a's worker
  auto d = backlog->enter(std::nullopt);            // its body still being read: counts for nothing yet
  EXPECT_NEAR(backlog->wait_seconds(), 10.0, 0.5);
  d->set_bytes(bytes_for(1.0));                     // a's worker at 10, free again at 11
  EXPECT_NEAR(backlog->wait_seconds(), 11.0, 0.5);
  d->set_bytes(bytes_for(5.0));                     // 10 + 5, past c's 14
  EXPECT_NEAR(backlog->wait_seconds(), 14.0, 0.5);
}

TEST(WorkBacklog, JobsAlreadyAdmittedAreRepredictedAtTheCurrentRate) {
  auto backlog = backlog_at_one_second_per_megabyte(1);
  auto a = backlog->enter(bytes_for(3.0));
  a->start();
  auto b = backlog->enter(bytes_for(2.0));
  EXPECT_NEAR(backlog->wait_seconds(), 5.0, 0.5);
  for (int i = 0; i < 30; ++i) backlog->learn(1'000'000, 2.0);  // the machine now runs at half the speed
  EXPECT_NEAR(backlog->wait_seconds(), 10.0, 0.5);
}

TEST(WorkBacklog, AJobLeavesWhenItsTicketIsDropped) {
  auto backlog = backlog_at_one_second_per_megabyte(1);
  auto a = backlog->enter(bytes_for(5.0));
  auto b = backlog->enter(bytes_for(3.0));
  a->start();
  EXPECT_EQ(backlog->size(), 2u);
  EXPECT_NEAR(backlog->wait_seconds(), 8.0, 0.5);
  a.reset();
  EXPECT_EQ(backlog->size(), 1u);
  EXPECT_NEAR(backlog->wait_seconds(), 3.0, 1e-3);
}

TEST(WorkBacklog, ARunningJobWithoutAPredictionHoldsItsWorkerForNothingMore) {
  auto backlog = backlog_at_one_second_per_megabyte(1);
  auto a = backlog->enter(std::nullopt);  // a label volume
  a->start();
  auto b = backlog->enter(bytes_for(2.0));
  EXPECT_NEAR(backlog->wait_seconds(), 2.0, 1e-3);
}

}  // namespace
}  // namespace wish::server
