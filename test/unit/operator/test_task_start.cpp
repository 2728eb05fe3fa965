// The scripted operator's start (operator/task_start.h): the task clock waits for the
// simulation's first status, or for the timeout, then holds the start delay.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "tissue_trainer/core/operator/task_start.h"

namespace tt {
namespace {

constexpr double kTick = 0.001;

// Ticks until the task time reaches 0; returns the elapsed time then (or -1 past `limit`).
double startOf(TaskStart& start, double statusAt, double limit = 100.0) {
  for (long tick = 0; tick * kTick <= limit; ++tick) {
    const double elapsed = tick * kTick;
    if (start.taskTime(elapsed, elapsed >= statusAt) >= 0.0) return elapsed;
  }
  return -1.0;
}

TEST(TaskStart, WaitsForTheSimulationsFirstStatusThenHoldsTheDelay) {
  TaskStart start(30.0, 1.0);
  EXPECT_EQ(start.wait(), TaskStart::Wait::kWaiting);
  EXPECT_NEAR(startOf(start, 8.0), 9.0, 1e-9);  // status at 8 s, then 1 s of holding
  EXPECT_EQ(start.wait(), TaskStart::Wait::kSimulation);
  EXPECT_NEAR(start.waitEnded(), 8.0, 1e-9);
}

TEST(TaskStart, TheTaskTimeRunsWithTheTicksOnceStarted) {
  TaskStart start(30.0, 0.5);
  for (double t = 0.0; t < 2.0; t += 0.1) EXPECT_LT(start.taskTime(t, false), 0.0);
  EXPECT_NEAR(start.taskTime(2.0, true), -0.5, 1e-12);
  EXPECT_NEAR(start.taskTime(3.0, true), 0.5, 1e-12);
  EXPECT_NEAR(start.taskTime(3.0, false), 0.5, 1e-12);  // the status need not keep coming
}

TEST(TaskStart, StartsWithoutTheSimulationAfterTheTimeout) {
  TaskStart start(5.0, 1.0);
  EXPECT_NEAR(startOf(start, std::numeric_limits<double>::infinity()), 6.0, 1e-9);
  EXPECT_EQ(start.wait(), TaskStart::Wait::kTimedOut);
  EXPECT_NEAR(start.waitEnded(), 5.0, 1e-9);
}

TEST(TaskStart, ZeroTimeoutDoesNotWait) {
  TaskStart start(0.0, 1.0);
  EXPECT_EQ(start.wait(), TaskStart::Wait::kNoWait);
  EXPECT_NEAR(startOf(start, std::numeric_limits<double>::infinity()), 1.0, 1e-9);
  EXPECT_EQ(start.wait(), TaskStart::Wait::kNoWait);
}

TEST(TaskStart, AStatusAlreadyThereStartsTheHoldAtOnce) {
  TaskStart start(30.0, 1.0);
  EXPECT_NEAR(startOf(start, 0.0), 1.0, 1e-9);
}

TEST(TaskStart, WhileWaitingTheTaskTimeIsBeforeTheHold) {
  TaskStart start(30.0, 1.0);
  EXPECT_LT(start.taskTime(29.9, false), -1.0);
}

TEST(TaskStart, RefusesBadTimes) {
  EXPECT_THROW(TaskStart(-1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(TaskStart(1.0, -1.0), std::invalid_argument);
  EXPECT_THROW(TaskStart(std::numeric_limits<double>::infinity(), 1.0), std::invalid_argument);
  EXPECT_THROW(TaskStart(1.0, std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace tt
