// Training assessment metrics on hand-computable sessions: a straight line at constant
// speed, a minimum-jerk reach, a force square pulse, a sinusoidal force, rejected samples,
// empty and one-sample input, gaps, settings validation and the YAML round trip.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "tissue_trainer/core/assess/assessment_report.h"
#include "tissue_trainer/core/assess/session_assessor.h"
#include "tissue_trainer/core/error.h"
#include "../random_draws.h"

namespace tt {
namespace {

using Eigen::Vector3d;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

double metric(const AssessmentReport& r, const std::string& key) {
  const Metric* m = r.find(key);
  EXPECT_NE(m, nullptr) << key;
  return m ? m->value : kNaN;
}
bool hasData(const AssessmentReport& r, const std::string& key) { return r.find(key)->hasData; }

// 0.05 m/s along (1, 2, 2) / 3 for 2 s, sampled at 1 kHz; optional position noise (m).
AssessmentReport straightLine(double noise) {
  SessionAssessor a{AssessmentSettings{}};
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  const Vector3d dir = Vector3d(1, 2, 2) / 3.0;
  for (int i = 0; i <= 2000; ++i) {
    const double t = 10.0 + i / 1000.0;
    Vector3d p = Vector3d(0.01, 0.02, 0.03) + dir * 0.05 * (i / 1000.0);
    if (noise > 0.0) p += noise * testutil::drawVector(n, rng);
    EXPECT_TRUE(a.addTip(t, p));
  }
  return a.report();
}

TEST(Assess, StraightLineAtConstantSpeed) {
  const AssessmentReport r = straightLine(0.0);
  EXPECT_EQ(r.tip.accepted, 2001u);
  EXPECT_NEAR(metric(r, "task_time"), 2.0, 1e-9);
  EXPECT_NEAR(metric(r, "path_length"), 0.1, 1e-12);
  EXPECT_EQ(metric(r, "movements"), 1.0);
  // 200 window means of 10 ms, centres 0.005 .. 1.995 s: 199 steps of 0.5 mm.
  EXPECT_NEAR(metric(r, "path_length_smoothed"), 0.0995, 1e-9);
  EXPECT_NEAR(metric(r, "motion_time"), 1.99, 1e-9);  // first to last grid point
  EXPECT_LT(metric(r, "mean_squared_jerk"), 1e-12);
  EXPECT_NEAR(metric(r, "economy_of_motion"), 1.0, 1e-9);
  EXPECT_NEAR(metric(r, "peak_speed_median"), 0.05, 1e-9);
  EXPECT_NEAR(metric(r, "idle_time"), 0.0, 1e-12);
}

TEST(Assess, NoisyLineStaysSmooth) {
  // 10 um of white noise per 1 kHz sample (a haptic encoder's order of magnitude): the raw
  // path length grows, the resampled and smoothed path does not, and the jerk stays far below
  // that of a real reach (a minimum-jerk 0.1 m / 2 s reach: 720 A^2 / T^6 = 0.1125 m^2/s^6).
  const AssessmentReport r = straightLine(1e-5);
  EXPECT_GT(metric(r, "path_length"), 0.105);
  EXPECT_NEAR(metric(r, "path_length_smoothed"), 0.0995, 0.002);
  EXPECT_EQ(metric(r, "movements"), 1.0);
  EXPECT_LT(metric(r, "mean_squared_jerk"), 0.1 * 0.1125);
}

// Minimum-jerk profile s(u) = 10u^3 - 15u^4 + 6u^5 and its third derivative.
double minimumJerk(double u) { return 10 * std::pow(u, 3) - 15 * std::pow(u, 4) + 6 * std::pow(u, 5); }
double minimumJerkJerk(double u) { return 60 - 360 * u + 360 * u * u; }

// The dimensionless jerk (1/2 integral of |d3x/dt3|^2 dt) T^5 / A^2 of a minimum-jerk reach of
// amplitude A in time T, by Simpson's rule on the analytic jerk (A / T^3) s'''(t / T).
double minimumJerkDimensionlessJerk(double A, double T) {
  const int n = 2000;  // even
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double u = double(i) / n, j = A / std::pow(T, 3) * minimumJerkJerk(u);
    sum += (i == 0 || i == n ? 1.0 : (i % 2 ? 4.0 : 2.0)) * j * j;
  }
  const double integral = sum * (T / n) / 3.0;
  return 0.5 * integral * std::pow(T, 5) / (A * A);
}

// A reach of A metres in T seconds, starting at `rest` s and resting `rest` s after, sampled
// at 1 kHz.
AssessmentReport reach(double A, double T, double rest, const AssessmentSettings& s = AssessmentSettings{}) {
  SessionAssessor a{s};
  const Vector3d dir = Vector3d(2, -1, 2) / 3.0;
  const int n = static_cast<int>(std::lround((T + 2 * rest) * 1000));
  for (int i = 0; i <= n; ++i) {
    const double t = i / 1000.0, u = std::min(1.0, std::max(0.0, (t - rest) / T));
    a.addTip(t, Vector3d(0.02, 0.05, 0.1) + A * minimumJerk(u) * dir);
  }
  return a.report();
}

TEST(Assess, MinimumJerkReach) {
  // The analytic value: 1/2 of 720 A^2 / T^5 times T^5 / A^2 = 360, whatever A and T.
  const double A = 0.1, T = 2.0;
  const double analytic = minimumJerkDimensionlessJerk(A, T);
  EXPECT_NEAR(analytic, 360.0, 1e-6);
  EXPECT_NEAR(minimumJerkDimensionlessJerk(0.03, 0.7), analytic, 1e-6);

  const AssessmentReport r = reach(A, T, 0.5);
  ASSERT_EQ(metric(r, "movements"), 1.0);
  ASSERT_EQ(r.movements.size(), 1u);
  const Movement& m = r.movements[0];
  EXPECT_NEAR(metric(r, "path_length"), A, 1e-12);
  EXPECT_NEAR(m.pathLength, A, 1e-4);
  EXPECT_NEAR(m.chord, A, 1e-4);
  EXPECT_NEAR(m.peakSpeed, 1.875 * A / T, 5e-3 * A / T);  // s'(1/2) = 15/8, a little smoothed
  // The movement spans the reach (widened down to the rest speed), not only the part above
  // the start and stop speeds (0.09 s shorter at each end for this reach).
  EXPECT_NEAR(m.start, 0.5, 0.05);
  EXPECT_NEAR(m.end, 0.5 + T, 0.05);
  ASSERT_TRUE(m.hasJerk);
  std::printf("[assess] minimum-jerk reach 0.1 m / 2 s: LDLJ %.4f (analytic %.4f), movement %.3f..%.3f s\n",
              m.logDimensionlessJerk, -std::log(analytic), m.start, m.end);
  EXPECT_NEAR(m.logDimensionlessJerk, -std::log(analytic), 0.05);
  EXPECT_EQ(metric(r, "ldlj_median"), m.logDimensionlessJerk);
  EXPECT_EQ(metric(r, "ldlj_worst"), m.logDimensionlessJerk);
  EXPECT_NEAR(metric(r, "economy_of_motion"), 1.0, 1e-3);
  // 720 A^2 / T^5 of squared jerk spread over the 3 s of the session (the smoothing takes
  // some of it: 91 %).
  EXPECT_NEAR(metric(r, "mean_squared_jerk"), 720 * A * A / std::pow(T, 5) / (T + 1.0),
              0.1 * 720 * A * A / std::pow(T, 5) / (T + 1.0));
}

// A reach through free space, then a press that touches the tissue: only the press is marked
// in contact, and the reach median takes only the reach.
TEST(Assess, MovementsInContactAreMarkedAndLeftOutOfTheReachMedian) {
  SessionAssessor a{AssessmentSettings{}};
  const Vector3d start(0.0, 0.05, 0.1), down(0, 0, -1);
  // 0.5 s rest, a 6 cm reach in 1.5 s, 1 s rest, a 1 cm press in 1 s made of two overlapping
  // minimum-jerk halves (less smooth than the reach), 0.5 s rest.
  auto position = [&](double t) -> Vector3d {
    const double reachU = std::clamp((t - 0.5) / 1.5, 0.0, 1.0);
    const double pressA = std::clamp((t - 3.0) / 0.6, 0.0, 1.0), pressB = std::clamp((t - 3.4) / 0.6, 0.0, 1.0);
    return start + (0.06 * minimumJerk(reachU) + 0.005 * minimumJerk(pressA) + 0.005 * minimumJerk(pressB)) * down;
  };
  for (int i = 0; i <= 4500; ++i) {
    const double t = i / 1000.0;
    a.addTip(t, position(t));
    if (i % 10 == 0) {
      const bool touching = t > 2.8 && t < 4.2;
      a.addForce(t, touching ? Vector3d(0, 0, 0.5) : Vector3d::Zero(), touching);
    }
  }
  const AssessmentReport r = a.report();
  ASSERT_EQ(r.movements.size(), 2u);
  EXPECT_FALSE(r.movements[0].inContact);
  EXPECT_TRUE(r.movements[1].inContact);
  ASSERT_TRUE(r.movements[0].hasJerk && r.movements[1].hasJerk);
  EXPECT_LT(r.movements[1].logDimensionlessJerk, r.movements[0].logDimensionlessJerk - 0.5);
  EXPECT_EQ(metric(r, "ldlj_reach_median"), r.movements[0].logDimensionlessJerk);
  EXPECT_DOUBLE_EQ(metric(r, "ldlj_median"),
                   0.5 * (r.movements[0].logDimensionlessJerk + r.movements[1].logDimensionlessJerk));
}

TEST(Assess, LogDimensionlessJerkIgnoresAmplitudeAndHardlyDuration) {
  // Hogan and Sternad 2009: the measure must not change with the reach's size or speed. The
  // size does not change it at all; the duration only through the smoothing (a 1 s reach
  // reads 0.17 lower than a 2 s one).
  const double base = reach(0.1, 2.0, 0.5).movements.at(0).logDimensionlessJerk;
  for (double A : {0.02, 0.03, 0.3}) {
    const AssessmentReport r = reach(A, 2.0, 0.5);
    ASSERT_EQ(r.movements.size(), 1u) << A << " m";
    EXPECT_NEAR(r.movements[0].logDimensionlessJerk, base, 1e-3) << A << " m";
  }
  for (double T : {1.0, 1.5, 3.0}) {
    const AssessmentReport r = reach(0.05, T, 0.5);
    ASSERT_EQ(r.movements.size(), 1u) << T << " s";
    EXPECT_NEAR(r.movements[0].logDimensionlessJerk, -std::log(360.0), 0.2) << T << " s";
  }
}

TEST(Assess, AnArrestInsideAReachLowersItsLogDimensionlessJerk) {
  // 10 cm in two minimum-jerk halves of 1 s with an arrest of 0.05 s between them (the speed
  // is below movement_speed_stop for about 0.15 s): one movement
  // (the pause is shorter than movement_min_pause), far less smooth than one 2.1 s reach;
  // with movement_min_pause 0 it is two smooth movements.
  auto arrested = [](const AssessmentSettings& s) {
    SessionAssessor a{s};
    for (int i = 0; i <= 3050; ++i) {
      const double t = i / 1000.0;
      const double u1 = std::clamp(t - 0.5, 0.0, 1.0), u2 = std::clamp(t - 1.55, 0.0, 1.0);
      a.addTip(t, Vector3d(0.05 * (minimumJerk(u1) + minimumJerk(u2)), 0, 0));
    }
    return a.report();
  };
  const AssessmentReport one = arrested(AssessmentSettings{});
  ASSERT_EQ(one.movements.size(), 1u);
  const double smooth = reach(0.1, 2.05, 0.5).movements.at(0).logDimensionlessJerk;
  std::printf("[assess] reach with an arrest: LDLJ %.3f, without: %.3f\n",
              one.movements[0].logDimensionlessJerk, smooth);
  EXPECT_LT(one.movements[0].logDimensionlessJerk, smooth - 1.0);
  EXPECT_NEAR(metric(one, "idle_time"), 0.0, 1e-12);

  AssessmentSettings split;
  split.movementMinPause = 0.0;
  const AssessmentReport two = arrested(split);
  ASSERT_EQ(two.movements.size(), 2u);
  for (const Movement& m : two.movements) EXPECT_NEAR(m.logDimensionlessJerk, -std::log(360.0), 0.2);
  // Each widened to the speed's minimum in the arrest, where they meet.
  EXPECT_NEAR(two.movements[0].end, 1.525, 0.02);
  EXPECT_NEAR(two.movements[1].start, two.movements[0].end, 1e-9);
}

TEST(Assess, MovementsWithHysteresis) {
  // Three reaches of 2 cm in 0.5 s separated by 0.5 s rests: three movements.
  SessionAssessor a{AssessmentSettings{}};
  for (int i = 0; i <= 3000; ++i) {
    const double t = i / 1000.0;
    const int reach = std::min(2, static_cast<int>(t));
    const double s = std::min(1.0, std::max(0.0, (t - reach) / 0.5));
    const double x = 0.02 * (reach + 10 * std::pow(s, 3) - 15 * std::pow(s, 4) + 6 * std::pow(s, 5));
    a.addTip(t, Vector3d(0, x, 0));
  }
  const AssessmentReport r = a.report();
  EXPECT_EQ(metric(r, "movements"), 3.0);
  EXPECT_NEAR(metric(r, "path_length"), 0.06, 1e-12);
  EXPECT_GT(metric(r, "motion_time"), 2.3);
  EXPECT_LT(metric(r, "motion_time"), 2.6);
  // Two rests of 0.5 s between the reaches, less what the smoothing (sigma 0.03 s) adds to
  // each end of each reach.
  EXPECT_GT(metric(r, "idle_time"), 0.7);
  EXPECT_LE(metric(r, "idle_time"), 1.0);
  EXPECT_GE(metric(r, "movement_duration_median"), 0.5);
  EXPECT_LT(metric(r, "movement_duration_median"), 0.65);
}

TEST(Assess, ForceSquarePulse) {
  // 2 N (along -y) for t in [1, 2) s, sampled at 100 Hz over 3 s, threshold 1.5 N.
  SessionAssessor a{AssessmentSettings{}};
  for (int i = 0; i <= 300; ++i) {
    const bool on = i >= 100 && i < 200;
    a.addForce(i / 100.0, on ? Vector3d(0, -2, 0) : Vector3d::Zero(), on);
  }
  const AssessmentReport r = a.report();
  EXPECT_NEAR(metric(r, "force_integral"), 2.0, 1e-9);
  EXPECT_NEAR(metric(r, "contact_time"), 1.0, 1e-9);
  EXPECT_NEAR(metric(r, "mean_force"), 2.0, 1e-9);
  EXPECT_NEAR(metric(r, "rms_force"), 2.0, 1e-9);
  EXPECT_EQ(metric(r, "peak_force"), 2.0);
  EXPECT_EQ(metric(r, "excessive_force_events"), 1.0);
  EXPECT_NEAR(metric(r, "excessive_force_time"), 1.0, 1e-9);
  EXPECT_NEAR(metric(r, "excess_force_integral"), 0.5, 1e-9);  // (2 - 1.5) N for 1 s
  EXPECT_NEAR(metric(r, "mean_force_rate"), 4.0 / 3.0, 1e-9);  // up 2 N, down 2 N in 3 s
  EXPECT_FALSE(hasData(r, "task_time"));
}

TEST(Assess, TwoPulsesAreTwoEvents) {
  SessionAssessor a{AssessmentSettings{}};
  for (int i = 0; i <= 400; ++i) {
    const bool on = (i >= 100 && i < 150) || (i >= 250 && i < 300);
    a.addForce(i / 100.0, on ? Vector3d(0, 0, 3) : Vector3d(0, 0, 1), true);
  }
  const AssessmentReport r = a.report();
  EXPECT_EQ(metric(r, "excessive_force_events"), 2.0);
  EXPECT_NEAR(metric(r, "excessive_force_time"), 1.0, 1e-9);
  EXPECT_NEAR(metric(r, "force_integral"), 3.0 * 1.0 + 1.0 * 3.0, 1e-9);
  EXPECT_NEAR(metric(r, "mean_force"), 6.0 / 4.0, 1e-9);
}

TEST(Assess, SinusoidRms) {
  // f = A sin(2 pi t / P) along x, 4 whole periods at 1 kHz: RMS A / sqrt 2, mean |f| 2A/pi,
  // mean |df/dt| = 4A per period = 24 N/s.
  const double A = 3.0, P = 0.5;
  SessionAssessor a{AssessmentSettings{}};
  for (int i = 0; i <= 2000; ++i) {
    const double t = i / 1000.0;
    a.addForce(t, Vector3d(A * std::sin(2 * M_PI * t / P), 0, 0), true);
  }
  const AssessmentReport r = a.report();
  EXPECT_NEAR(metric(r, "rms_force"), A / std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(metric(r, "mean_force"), 2 * A / M_PI, 1e-4);
  EXPECT_NEAR(metric(r, "peak_force"), A, 1e-12);
  EXPECT_NEAR(metric(r, "mean_force_rate"), 8 * A, 1e-9);
  EXPECT_EQ(metric(r, "excessive_force_events"), 4.0 * 2);  // |f| > 1.5 N twice a period
}

TEST(Assess, RejectedSamplesAreCountedAndIgnored) {
  SessionAssessor clean{AssessmentSettings{}}, dirty{AssessmentSettings{}};
  for (int i = 0; i <= 500; ++i) {
    const double t = i / 1000.0;
    const Vector3d p(0.1 * t, 0, 0);
    const Vector3d f(0, std::sin(t), 0);
    clean.addTip(t, p);
    clean.addForce(t, f, true);
    clean.addStatus(t, t, 1e-6 * t);
    dirty.addTip(t, p);
    dirty.addForce(t, f, true);
    dirty.addStatus(t, t, 1e-6 * t);
    if (i == 100) {
      EXPECT_FALSE(dirty.addTip(t, Vector3d(kNaN, 0, 0)));       // duplicate time, non-finite
      EXPECT_FALSE(dirty.addTip(t + 0.0005, Vector3d(kInf, 0, 0)));
      EXPECT_FALSE(dirty.addTip(kNaN, p));
      EXPECT_FALSE(dirty.addTip(t - 0.01, p));                  // earlier
      EXPECT_FALSE(dirty.addTip(t, p));                         // same time again
      EXPECT_FALSE(dirty.addForce(t + 0.0005, Vector3d(0, kNaN, 0), true));
      EXPECT_FALSE(dirty.addForce(t - 1.0, f, true));
      EXPECT_FALSE(dirty.addStatus(t + 0.0005, kInf, 0.0));
      EXPECT_FALSE(dirty.addStatus(t + 0.0005, 0.0, kNaN));
      EXPECT_FALSE(dirty.addStatus(t, 0.0, 0.0));
    }
  }
  const AssessmentReport a = clean.report(), b = dirty.report();
  EXPECT_EQ(b.tip.accepted, 501u);
  EXPECT_EQ(b.tip.nonFinite, 3u);
  EXPECT_EQ(b.tip.outOfOrder, 2u);
  EXPECT_EQ(b.force.nonFinite, 1u);
  EXPECT_EQ(b.force.outOfOrder, 1u);
  EXPECT_EQ(b.status.nonFinite, 2u);
  EXPECT_EQ(b.status.outOfOrder, 1u);
  ASSERT_EQ(a.metrics.size(), b.metrics.size());
  for (std::size_t i = 0; i < a.metrics.size(); ++i)
    EXPECT_EQ(a.metrics[i].value, b.metrics[i].value) << a.metrics[i].key;
  EXPECT_NEAR(metric(b, "peak_strain"), 0.5, 1e-15);
  EXPECT_NEAR(metric(b, "peak_strained_volume"), 0.5e-6, 1e-18);
}

TEST(Assess, EmptyAndOneSampleInputAreFiniteAndSayNoData) {
  SessionAssessor a{AssessmentSettings{}};
  AssessmentReport r = a.report();
  ASSERT_EQ(r.metrics.size(), 24u);
  for (const Metric& m : r.metrics) {
    EXPECT_TRUE(std::isfinite(m.value)) << m.key;
    EXPECT_FALSE(m.hasData) << m.key;
  }
  const YAML::Node y = YAML::Load(assessmentYaml(r, "empty"));
  EXPECT_EQ(y["no_data"].size(), 24u);
  EXPECT_NE(assessmentMarkdown(r, "empty").find("| task_time | no data |"), std::string::npos);

  a.addTip(1.0, Vector3d(1, 2, 3));
  a.addForce(1.0, Vector3d(0, 0.5, 0), true);
  a.addStatus(1.0, 0.2, 1e-7);
  r = a.report();
  for (const Metric& m : r.metrics) EXPECT_TRUE(std::isfinite(m.value)) << m.key;
  EXPECT_FALSE(hasData(r, "task_time"));
  EXPECT_FALSE(hasData(r, "movements"));
  EXPECT_FALSE(hasData(r, "mean_squared_jerk"));
  EXPECT_FALSE(hasData(r, "force_integral"));
  EXPECT_FALSE(hasData(r, "mean_force"));
  EXPECT_TRUE(hasData(r, "peak_force"));
  EXPECT_EQ(metric(r, "peak_force"), 0.5);
  EXPECT_EQ(metric(r, "peak_strain"), 0.2);
}

TEST(Assess, GapsCarryNoWeight) {
  // Samples every 10 ms over [0, 1] and [3, 4] s; max_gap 0.5 s. The jump of the tip between
  // the two parts counts in the raw path length; the force held across the gap does not.
  SessionAssessor a{AssessmentSettings{}};
  for (int i = 0; i <= 400; ++i) {
    if (i > 100 && i < 300) continue;
    const double t = i / 100.0;
    a.addTip(t, Vector3d(i < 200 ? 0.0 : 0.05, 0, 0));
    a.addForce(t, Vector3d(1, 0, 0), true);
  }
  const AssessmentReport r = a.report();
  EXPECT_NEAR(metric(r, "task_time"), 4.0, 1e-12);
  EXPECT_NEAR(metric(r, "path_length"), 0.05, 1e-15);
  EXPECT_NEAR(metric(r, "path_length_smoothed"), 0.0, 1e-12);
  EXPECT_EQ(metric(r, "movements"), 0.0);
  EXPECT_NEAR(metric(r, "contact_time"), 2.0, 1e-9);
  EXPECT_NEAR(metric(r, "force_integral"), 2.0, 1e-9);
}

TEST(Assess, SmoothingKeepsLinesExact) {
  std::vector<Vector3d> x;
  for (int i = 0; i < 7; ++i) x.push_back(Vector3d(i, 2.0 * i, -0.5 * i));
  for (double sigma : {0.5, 2.0, 10.0}) {
    const auto y = smoothPath(x, sigma);
    for (int i = 0; i < 7; ++i) EXPECT_LT((y[i] - x[i]).norm(), 1e-12) << sigma << " " << i;
  }
}

TEST(Assess, SettingsAreValidated) {
  AssessmentSettings s;
  EXPECT_NO_THROW(s.validate());
  s.movementSpeedStop = 0.02;
  try {
    s.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("movement_speed_stop"), std::string::npos) << e.what();
  }
  s = AssessmentSettings{};
  s.forceThreshold = kNaN;
  EXPECT_THROW(SessionAssessor{s}, std::invalid_argument);

  const std::string file = testing::TempDir() + "assess_settings.yaml";
  std::ofstream(file) << "force_threshold: 3\nmax_gap: 0.25\noutput_dir: x\n";
  const AssessmentSettings loaded = loadAssessmentSettings(file);
  EXPECT_EQ(loaded.forceThreshold, 3.0);
  EXPECT_EQ(loaded.maxGap, 0.25);
  std::ofstream(file) << "force_treshold: 3\n";
  EXPECT_THROW(loadAssessmentSettings(file), InputError);
  std::ofstream(file) << "resample_rate: fast\n";
  EXPECT_THROW(loadAssessmentSettings(file), InputError);
  std::ofstream(file) << "smoothing_time: -1\n";
  EXPECT_THROW(loadAssessmentSettings(file), InputError);
  std::remove(file.c_str());
  EXPECT_THROW(loadAssessmentSettings(file), InputError);
}

TEST(Assess, ASimulationRestartIsSkippedAndReported) {
  // Force 1 N every 10 ms over [0, 1] s and again from 1.3 s to 2 s: a gap shorter than
  // max_gap (0.5 s), so only the restart flag keeps the last sample from holding over it.
  // The tip stream starts at 0.5 s: restart times count from the session's first sample.
  SessionAssessor plain{AssessmentSettings{}}, restarted{AssessmentSettings{}};
  for (int i = 0; i <= 200; ++i) {
    if (i > 100 && i < 130) continue;
    const double t = i / 100.0;
    const Vector3d f = i <= 100 ? Vector3d(1, 0, 0) : Vector3d(0, 2, 0);
    plain.addForce(t, f, true);
    restarted.addForce(t, f, true, i == 130);
    if (i >= 50) restarted.addTip(t, Vector3d::Zero());
  }
  const AssessmentReport p = plain.report(), r = restarted.report();
  EXPECT_TRUE(p.restarts.empty());
  EXPECT_NEAR(metric(p, "contact_time"), 2.0, 1e-9);
  EXPECT_NEAR(metric(r, "contact_time"), 1.7, 1e-9);
  EXPECT_NEAR(metric(r, "force_integral"), 1.0 + 2.0 * 0.7, 1e-9);
  // The jump across the restart is no change of force the trainee made.
  EXPECT_NEAR(metric(r, "mean_force_rate"), 0.0, 1e-9);
  ASSERT_EQ(r.restarts.size(), 1u);
  EXPECT_NEAR(r.restarts[0].time, 1.3, 1e-12);
  EXPECT_NEAR(r.restarts[0].gap, 0.3, 1e-12);
  EXPECT_NE(assessmentMarkdown(r, "x").find("Simulation restarted at t = 1.3 s"), std::string::npos);
  const YAML::Node y = YAML::Load(assessmentYaml(r, "x"));
  ASSERT_EQ(y["simulation_restarts"].size(), 1u);
  EXPECT_EQ(y["simulation_restarts"][0]["time"].as<double>(), r.restarts[0].time);
  // The very first sample cannot follow a restart.
  SessionAssessor first{AssessmentSettings{}};
  first.addForce(0.0, Vector3d::Zero(), false, true);
  EXPECT_TRUE(first.report().restarts.empty());
}

TEST(Assess, YamlRoundTripIsExact) {
  SessionAssessor a{AssessmentSettings{}};
  // One movement (the first second) through free space, then contact at rest: every metric,
  // the reach median too, has data.
  for (int i = 0; i <= 1600; ++i) {
    const double t = i / 1000.0, moving = std::min(t, 1.0);
    a.addTip(t, Vector3d(0.03 * std::sin(3 * moving), 0.01 * moving * moving, 0));
    a.addForce(t, Vector3d(0, 1.7 * std::sin(5 * t), 0), t > 1.4 && i % 3 != 0);
    a.addStatus(t, 0.1 * t, 1e-6 * t);
  }
  const AssessmentReport r = a.report();
  const YAML::Node y = YAML::Load(assessmentYaml(r, "test"));
  EXPECT_EQ(y["source"].as<std::string>(), "test");
  EXPECT_EQ(y["samples"]["tip"]["accepted"].as<std::size_t>(), 1601u);
  for (const Metric& m : r.metrics) EXPECT_EQ(y["metrics"][m.key].as<double>(), m.value) << m.key;
  EXPECT_EQ(y["no_data"].size(), 0u);
  EXPECT_EQ(y["simulation_restarts"].size(), 0u);
  EXPECT_EQ(y["settings"]["force_threshold"].as<double>(), 1.5);
}

}  // namespace
}  // namespace tt
