// The work backlog (server/work_backlog.hpp): what it predicts from the jobs it learned, and the wait it predicts
// for a job admitted now (the workers taken first in, first out).

#include "server/work_backlog.hpp"

#include <cmath>
#include <memory>

#include <gtest/gtest.h>

namespace wish::server {
namespace {

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
  auto backlog = std::make_shared<WorkBacklog>(2);
  auto running = backlog->enter(10.0);
  running->start();
  EXPECT_EQ(backlog->wait_seconds(), 0.0);
}

TEST(WorkBacklog, WaitingJobsTakeTheFirstFreeWorkerInTurn) {
  auto backlog = std::make_shared<WorkBacklog>(2);
  auto a = backlog->enter(10.0);
  auto b = backlog->enter(6.0);
  a->start();
  b->start();
  EXPECT_NEAR(backlog->wait_seconds(), 6.0, 0.5);   // b's worker is free first
  auto c = backlog->enter(8.0);                     // waits for b's worker: free again at 14
  EXPECT_NEAR(backlog->wait_seconds(), 10.0, 0.5);  // a's worker
  auto d = backlog->enter(1.0);                     // a's worker at 10, free again at 11
  EXPECT_NEAR(backlog->wait_seconds(), 11.0, 0.5);
  d->repredict(5.0);                                // its bytes read: 10 + 5, past c's 14
  EXPECT_NEAR(backlog->wait_seconds(), 14.0, 0.5);
}

TEST(WorkBacklog, AJobLeavesWhenItsTicketIsDropped) {
  auto backlog = std::make_shared<WorkBacklog>(1);
  auto a = backlog->enter(5.0);
  auto b = backlog->enter(3.0);
  a->start();
  EXPECT_EQ(backlog->size(), 2u);
  EXPECT_NEAR(backlog->wait_seconds(), 8.0, 0.5);
  a.reset();
  EXPECT_EQ(backlog->size(), 1u);
  EXPECT_NEAR(backlog->wait_seconds(), 3.0, 1e-9);
}

TEST(WorkBacklog, ARunningJobPastItsPredictionHoldsItsWorkerForNothingMore) {
  auto backlog = std::make_shared<WorkBacklog>(1);
  auto a = backlog->enter(0.0);  // unknown
  a->start();
  auto b = backlog->enter(2.0);
  EXPECT_NEAR(backlog->wait_seconds(), 2.0, 1e-9);
}

}  // namespace
}  // namespace wish::server
