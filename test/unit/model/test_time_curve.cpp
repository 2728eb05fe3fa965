// Time curves: values at hand-computed times, periodicity, continuity of the curve and of the
// twitch's slope, and the YAML reader on well-formed curves (malformed_time_curve.cpp has the
// errors).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "tissue_trainer/core/model/time_curve.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {
namespace {

constexpr double kPi = 3.14159265358979323846;

TimeCurve::Twitch exampleTwitch() {
  TimeCurve::Twitch w;
  w.period = 1.0;
  w.peak = 10.0;
  w.riseTime = 0.2;
  w.decayTime = 0.4;
  w.onset = 0.1;
  return w;
}

TEST(TimeCurve, DefaultIsZeroAndConstantIsConstant) {
  EXPECT_EQ(TimeCurve().value(3.0), 0.0);
  const TimeCurve c = TimeCurve::constant(2.5);
  for (double t : {-10.0, 0.0, 0.3, 1e6}) EXPECT_EQ(c.value(t), 2.5);
}

TEST(TimeCurve, PiecewiseLinearAtHandComputedTimes) {
  const TimeCurve c = TimeCurve::piecewiseLinear({0.0, 1.0, 3.0}, {0.0, 2.0, -2.0});
  EXPECT_DOUBLE_EQ(c.value(0.0), 0.0);
  EXPECT_DOUBLE_EQ(c.value(0.5), 1.0);
  EXPECT_DOUBLE_EQ(c.value(1.0), 2.0);
  EXPECT_DOUBLE_EQ(c.value(2.0), 0.0);
  EXPECT_DOUBLE_EQ(c.value(2.5), -1.0);
  EXPECT_DOUBLE_EQ(c.value(3.0), -2.0);
  EXPECT_DOUBLE_EQ(c.value(-1.0), 0.0);   // the first value before the first key
  EXPECT_DOUBLE_EQ(c.value(50.0), -2.0);  // the last value held after the last key
  const TimeCurve single = TimeCurve::piecewiseLinear({0.4}, {7.0});
  EXPECT_EQ(single.value(0.0), 7.0);
  EXPECT_EQ(single.value(9.0), 7.0);
}

TEST(TimeCurve, PiecewiseLinearIsContinuousAtItsKeys) {
  const TimeCurve c = TimeCurve::piecewiseLinear({-0.5, 0.1, 0.2, 2.0}, {1.0, -3.0, 4.0, 4.5});
  const double h = 1e-9;
  for (double t : {-0.5, 0.1, 0.2, 2.0}) EXPECT_NEAR(c.value(t - h), c.value(t + h), 1e-7) << t;
}

TEST(TimeCurve, TwitchAtHandComputedTimes) {
  const TimeCurve c = TimeCurve::twitch(exampleTwitch());
  // s = t - 0.1; rise on s in [0, 0.2), decay on [0.2, 0.6), rest on [0.6, 1).
  const double eighth = 5.0 * (1.0 - std::sqrt(0.5));  // 10 (1 - cos(pi/4)) / 2
  EXPECT_NEAR(c.value(0.05), 0.0, 1e-12);
  EXPECT_NEAR(c.value(0.1), 0.0, 1e-12);
  EXPECT_NEAR(c.value(0.15), eighth, 1e-12);
  EXPECT_NEAR(c.value(0.2), 5.0, 1e-12);
  EXPECT_NEAR(c.value(0.3), 10.0, 1e-12);
  EXPECT_NEAR(c.value(0.5), 5.0, 1e-12);
  EXPECT_NEAR(c.value(0.6), eighth, 1e-12);  // 10 (1 + cos(3 pi / 4)) / 2
  EXPECT_NEAR(c.value(0.7), 0.0, 1e-12);
  EXPECT_NEAR(c.value(0.95), 0.0, 1e-12);
  EXPECT_NEAR(c.value(1.3), 10.0, 1e-12);  // the next period
}

TEST(TimeCurve, TwitchIsPeriodicAndBetweenZeroAndPeak) {
  const TimeCurve::Twitch w = exampleTwitch();
  const TimeCurve c = TimeCurve::twitch(w);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int i = 0; i < 200; ++i) {
    const double t = u(rng);
    const double v = c.value(t);
    EXPECT_GE(v, -1e-12);
    EXPECT_LE(v, w.peak + 1e-12);
    for (int k : {-3, -1, 1, 2, 7}) EXPECT_NEAR(c.value(t + k * w.period), v, 1e-9) << t << " " << k;
  }
}

// |v(t + h) - v(t)| <= h max|v'| everywhere (no jump), and at the joints (onset, peak, end of
// the decay, the period's end) the one-sided slopes agree (C1).
TEST(TimeCurve, TwitchIsContinuousWithAContinuousSlope) {
  const TimeCurve::Twitch w = exampleTwitch();
  const TimeCurve c = TimeCurve::twitch(w);
  const double maxSlope = 0.5 * kPi * w.peak / std::min(w.riseTime, w.decayTime);
  const double h = 1e-5;
  for (double t = -1.0; t < 2.0; t += 0.37e-3)
    EXPECT_LE(std::abs(c.value(t + h) - c.value(t)), h * maxSlope * (1.0 + 1e-6)) << t;

  auto slopeJump = [&](double t, double d) {
    return std::abs((c.value(t + d) - c.value(t)) / d - (c.value(t) - c.value(t - d)) / d);
  };
  const double joints[] = {w.onset, w.onset + w.riseTime, w.onset + w.riseTime + w.decayTime,
                           w.onset + w.period};
  for (double t : joints) {
    // The slope jump of a C1 curve vanishes with d (here like d |v''|); a kink would not.
    EXPECT_LT(slopeJump(t, 1e-4), 2e-4 * w.peak * kPi * kPi / (w.riseTime * w.riseTime)) << t;
    EXPECT_LT(slopeJump(t, 1e-5), 0.2 * slopeJump(t, 1e-4) + 1e-6) << t;
  }
  // The same check sees the kink of a piecewise linear curve.
  const TimeCurve kink = TimeCurve::piecewiseLinear({0.0, 1.0, 2.0}, {0.0, 1.0, 0.0});
  const double jump = std::abs((kink.value(1.0 + 1e-5) - kink.value(1.0)) / 1e-5 -
                               (kink.value(1.0) - kink.value(1.0 - 1e-5)) / 1e-5);
  EXPECT_NEAR(jump, 2.0, 1e-6);
}

TEST(TimeCurve, TwitchFillingThePeriodAndStartingAtZero) {
  TimeCurve::Twitch w;
  w.period = 0.8;
  w.peak = -3.0;  // any sign
  w.riseTime = 0.3;
  w.decayTime = 0.5;
  const TimeCurve c = TimeCurve::twitch(w);
  EXPECT_NEAR(c.value(0.0), 0.0, 1e-12);
  EXPECT_NEAR(c.value(0.3), -3.0, 1e-12);
  EXPECT_NEAR(c.value(0.55), -1.5, 1e-12);
  EXPECT_NEAR(c.value(0.8 - 1e-9), 0.0, 1e-9);
  EXPECT_NEAR(c.value(-0.5), -3.0, 1e-12);  // periodic before 0 too
}

TEST(TimeCurve, FactoriesRefuseBadParameters) {
  EXPECT_THROW(TimeCurve::constant(NAN), std::invalid_argument);
  EXPECT_THROW(TimeCurve::piecewiseLinear({}, {}), std::invalid_argument);
  EXPECT_THROW(TimeCurve::piecewiseLinear({0.0, 1.0}, {1.0}), std::invalid_argument);
  EXPECT_THROW(TimeCurve::piecewiseLinear({0.0, 0.0}, {1.0, 2.0}), std::invalid_argument);
  EXPECT_THROW(TimeCurve::piecewiseLinear({1.0, 0.0}, {1.0, 2.0}), std::invalid_argument);
  TimeCurve::Twitch w = exampleTwitch();
  w.decayTime = 0.85;
  EXPECT_THROW(TimeCurve::twitch(w), std::invalid_argument);
  w = exampleTwitch();
  w.riseTime = 0.0;
  EXPECT_THROW(TimeCurve::twitch(w), std::invalid_argument);
  w = exampleTwitch();
  w.onset = 1.0;
  EXPECT_THROW(TimeCurve::twitch(w), std::invalid_argument);
}

TimeCurve read(const std::string& text, double scale = 1.0) {
  static const std::string file = "curve.yaml";
  return readTimeCurve(YamlEntry(YAML::Load(text), "curve", &file), scale);
}

TEST(TimeCurve, ReadsEachType) {
  EXPECT_EQ(read("{type: constant, value: -4}").value(1.0), -4.0);
  EXPECT_EQ(read("{type: constant, value: 2}", 1e3).value(1.0), 2e3);

  const TimeCurve p = read("{type: piecewise_linear, times: [0, 1, 3], values: [0, 2, -2]}", 10.0);
  EXPECT_EQ(p.kind(), TimeCurve::Kind::kPiecewiseLinear);
  EXPECT_DOUBLE_EQ(p.value(2.5), -10.0);

  const TimeCurve t = read(
      "type: twitch\nperiod: 1.0\npeak: 10\nrise_time: 0.2\ndecay_time: 0.4\nonset: 0.1\n", 2.0);
  const TimeCurve expected = TimeCurve::twitch(exampleTwitch());
  EXPECT_EQ(t.kind(), TimeCurve::Kind::kTwitch);
  for (double s = 0.0; s < 2.0; s += 0.01) EXPECT_NEAR(t.value(s), 2.0 * expected.value(s), 1e-12);
  // onset defaults to 0
  EXPECT_NEAR(read("{type: twitch, period: 1, peak: 4, rise_time: 0.5, decay_time: 0.5}").value(0.5),
              4.0, 1e-12);
}

TEST(TimeCurve, KnowsItsTypeNames) {
  for (const char* name : {"constant", "piecewise_linear", "twitch"}) EXPECT_TRUE(isTimeCurveType(name));
  for (const char* name : {"sawtooth", "Constant", "", "edge_length"}) EXPECT_FALSE(isTimeCurveType(name));
}

}  // namespace
}  // namespace tt
