// The simulation node's real-time clock (scene/real_time_clock.h): on-time frames keep the
// nominal step, a late frame covers the wall time that passed, never more than the maximum
// step, and every second of wall time is either simulated or reported as dropped.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include "tissue_trainer/core/scene/real_time_clock.h"

namespace tt {
namespace {

constexpr double kNominal = 0.01, kMax = 0.05;

// Runs frames that start at the given wall times, each advancing what it was given.
std::vector<ClockStep> play(RealTimeClock& clock, const std::vector<double>& starts) {
  std::vector<ClockStep> steps;
  for (double w : starts) {
    steps.push_back(clock.next(w));
    clock.advanced(steps.back().step);
  }
  return steps;
}

TEST(RealTimeClock, AnOnTimeRunKeepsTheNominalStep) {
  RealTimeClock clock(kNominal, kMax);
  const double origin = 1234.5;
  for (int k = 0; k < 1000; ++k) {
    const ClockStep s = clock.next(origin + k * kNominal);
    EXPECT_NEAR(s.step, kNominal, 1e-9) << "frame " << k;
    EXPECT_EQ(s.dropped, 0.0);
    clock.advanced(s.step);
    EXPECT_NEAR(clock.nextStart(), origin + (k + 1) * kNominal, 1e-9);
  }
  EXPECT_EQ(clock.totalDropped(), 0.0);
}

TEST(RealTimeClock, ASlowFrameMakesTheNextOneLongerAndItStartsAtOnce) {
  RealTimeClock clock(kNominal, kMax);
  ClockStep s = clock.next(0.0);
  clock.advanced(s.step);
  // The first frame took 25 ms: the second starts at once, at 25 ms, and must bring the
  // simulation to the end of its own period, 35 ms.
  EXPECT_LT(clock.nextStart(), 0.025);
  s = clock.next(0.025);
  EXPECT_NEAR(s.step, 0.025, 1e-12);
  EXPECT_EQ(s.dropped, 0.0);
  clock.advanced(s.step);
  EXPECT_NEAR(clock.nextStart(), 0.035, 1e-12);
  // Back on time: the nominal step again.
  s = clock.next(0.035);
  EXPECT_NEAR(s.step, kNominal, 1e-12);
}

TEST(RealTimeClock, NeverCoversMoreThanTheMaximumStepAndReportsTheRest) {
  RealTimeClock clock(kNominal, kMax);
  clock.advanced(clock.next(0.0).step);
  // A frame of 1 s: the next may cover 50 ms of it; 0.95 s of wall time is dropped.
  ClockStep s = clock.next(1.0);
  EXPECT_DOUBLE_EQ(s.step, kMax);
  EXPECT_NEAR(s.dropped, 1.0 - kMax, 1e-12);
  clock.advanced(s.step);
  // The schedule restarts from the dropped time: the frame after it is on time.
  EXPECT_NEAR(clock.nextStart(), 1.0 + kNominal, 1e-12);
  s = clock.next(1.0 + kNominal);
  EXPECT_NEAR(s.step, kNominal, 1e-12);
  EXPECT_EQ(s.dropped, 0.0);
  EXPECT_NEAR(clock.totalDropped(), 1.0 - kMax, 1e-12);
}

TEST(RealTimeClock, EveryWallSecondIsSimulatedOrDroppedAndNeverMoreThanTheMaximumBehind) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> frameWall(0.0, 0.2);  // up to 4 maximum steps
  RealTimeClock clock(kNominal, kMax);
  double w = 10.0, simulated = 0.0, dropped = 0.0;
  const double first = w;
  for (int k = 0; k < 2000; ++k) {
    const ClockStep s = clock.next(w);
    EXPECT_GE(s.step, kNominal);
    EXPECT_LE(s.step, kMax);
    EXPECT_GE(s.dropped, 0.0);
    if (s.dropped > 0.0) EXPECT_DOUBLE_EQ(s.step, kMax) << "dropped time while the step had room";
    // Behind at the start of this frame: the wall time since the first frame not yet simulated
    // nor given up, plus this frame's own period; this frame covers it, up to the maximum.
    const double behind = (w - first) + kNominal - simulated - dropped;
    EXPECT_LE(behind - s.dropped, kMax + 1e-9) << "frame " << k;
    EXPECT_NEAR(s.step, behind - s.dropped, 1e-9) << "frame " << k;
    clock.advanced(s.step);
    simulated += s.step;
    dropped += s.dropped;
    // The next frame starts when this one ends or, if it ended early, when it is due.
    w = std::max(w + frameWall(random), clock.nextStart());
  }
  EXPECT_NEAR(clock.totalDropped(), dropped, 1e-9);
}

TEST(RealTimeClock, AFrameThatStartsEarlyStillTakesTheNominalStep) {
  RealTimeClock clock(kNominal, kMax);
  clock.advanced(clock.next(0.0).step);
  const ClockStep s = clock.next(0.0099);  // the timer fired 0.1 ms early
  EXPECT_DOUBLE_EQ(s.step, kNominal);
  clock.advanced(s.step);
  EXPECT_NEAR(clock.nextStart(), 0.02, 1e-12);  // the next frame waits for its time
}

TEST(RealTimeClock, AFailedFrameIsCoveredByTheNext) {
  RealTimeClock clock(kNominal, kMax);
  clock.advanced(clock.next(0.0).step);
  const ClockStep failed = clock.next(0.01);
  clock.advanced(0.0);  // the state was restored
  EXPECT_LE(clock.nextStart(), 0.01 + 1e-12);  // the retry is due at once
  const ClockStep retry = clock.next(0.02);
  EXPECT_NEAR(retry.step, failed.step + kNominal, 1e-12);
}

TEST(RealTimeClock, RestartTakesANewOrigin) {
  RealTimeClock clock(kNominal, kMax);
  play(clock, {0.0, 0.01, 0.02});
  clock.restart();
  const std::vector<ClockStep> steps = play(clock, {100.0, 100.01});
  EXPECT_DOUBLE_EQ(steps[0].step, kNominal);
  EXPECT_NEAR(steps[1].step, kNominal, 1e-9);
  EXPECT_EQ(clock.totalDropped(), 0.0);
}

TEST(RealTimeClock, RefusesSteps) {
  EXPECT_THROW(RealTimeClock(0.0, 0.1), std::invalid_argument);
  EXPECT_THROW(RealTimeClock(-0.01, 0.1), std::invalid_argument);
  EXPECT_THROW(RealTimeClock(0.01, 0.005), std::invalid_argument);
  EXPECT_THROW(RealTimeClock(0.01, std::numeric_limits<double>::infinity()), std::invalid_argument);
  EXPECT_THROW(RealTimeClock(std::nan(""), 0.1), std::invalid_argument);
  EXPECT_NO_THROW(RealTimeClock(0.01, 0.01));
}

}  // namespace
}  // namespace tt
