// Training assessment metrics on hand-computable sessions: a straight line at constant
// speed, a minimum-jerk reach, a force square pulse, a sinusoidal force, rejected samples,
// empty and one-sample input, gaps, settings validation and the YAML round trip.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

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
    if (noise > 0.0) p += noise * Vector3d(n(rng), n(rng), n(rng));
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
  EXPECT_LT(metric(r, "dimensionless_jerk"), 1e-6);
  EXPECT_TRUE(hasData(r, "dimensionless_jerk"));
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

TEST(Assess, MinimumJerkReach) {
  // x(t) = A (10 s^3 - 15 s^4 + 6 s^5), s = t / T: integral of jerk^2 = 720 A^2 / T^5, so the
  // dimensionless jerk (T^5 / A^2 times that) is 720; one movement.
  const double A = 0.1, T = 2.0;
  SessionAssessor a{AssessmentSettings{}};
  for (int i = 0; i <= 2000; ++i) {
    const double s = i / 2000.0;
    a.addTip(i / 1000.0, Vector3d(A * (10 * std::pow(s, 3) - 15 * std::pow(s, 4) + 6 * std::pow(s, 5)), 0, 0));
  }
  const AssessmentReport r = a.report();
  EXPECT_EQ(metric(r, "movements"), 1.0);
  EXPECT_NEAR(metric(r, "path_length"), A, 1e-12);
  EXPECT_NEAR(metric(r, "dimensionless_jerk"), 720.0, 0.05 * 720.0);
  EXPECT_NEAR(metric(r, "mean_squared_jerk"), 720 * A * A / std::pow(T, 6), 0.05 * 720 * A * A / std::pow(T, 6));
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
  ASSERT_EQ(r.metrics.size(), 17u);
  for (const Metric& m : r.metrics) {
    EXPECT_TRUE(std::isfinite(m.value)) << m.key;
    EXPECT_FALSE(m.hasData) << m.key;
  }
  const YAML::Node y = YAML::Load(assessmentYaml(r, "empty"));
  EXPECT_EQ(y["no_data"].size(), 17u);
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
  for (int i = 0; i <= 1000; ++i) {
    const double t = i / 1000.0;
    a.addTip(t, Vector3d(0.03 * std::sin(3 * t), 0.01 * t * t, 0));
    a.addForce(t, Vector3d(0, 1.7 * std::sin(5 * t), 0), i % 3 != 0);
    a.addStatus(t, 0.1 * t, 1e-6 * t);
  }
  const AssessmentReport r = a.report();
  const YAML::Node y = YAML::Load(assessmentYaml(r, "test"));
  EXPECT_EQ(y["source"].as<std::string>(), "test");
  EXPECT_EQ(y["samples"]["tip"]["accepted"].as<std::size_t>(), 1001u);
  for (const Metric& m : r.metrics) EXPECT_EQ(y["metrics"][m.key].as<double>(), m.value) << m.key;
  EXPECT_EQ(y["no_data"].size(), 0u);
  EXPECT_EQ(y["simulation_restarts"].size(), 0u);
  EXPECT_EQ(y["settings"]["force_threshold"].as<double>(), 1.5);
}

}  // namespace
}  // namespace tt
