// Haptic bridge logic: force extrapolation from contact models (f = f0 - K (x - x0) with
// K = -df/dx), blending between models, the safety filter's guarantees, loop statistics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>

#include "tissue_trainer/core/haptics/force_extrapolator.h"
#include "tissue_trainer/core/haptics/haptic_pipeline.h"
#include "tissue_trainer/core/haptics/loop_stats.h"
#include "tissue_trainer/core/haptics/safety_filter.h"
#include "tissue_trainer/core/haptics/wall_probe.h"
#include "../random_draws.h"

namespace tt {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

ContactModel contact(std::uint64_t seq, const Vector3d& x0, const Vector3d& f0,
                     const Matrix3d& K = Matrix3d::Zero(), bool inContact = true) {
  ContactModel m;
  m.sequence = seq;
  m.stamp = m.simTime = 0.01 * static_cast<double>(seq);
  m.inContact = inContact;
  m.x0 = x0;
  m.f0 = f0;
  m.K = K;
  return m;
}

// A linear spring tissue f(x) = -S (x - rest) with S symmetric positive definite.
struct SpringTissue {
  Matrix3d S;
  Vector3d rest;
  Vector3d force(const Vector3d& x) const { return -S * (x - rest); }
  ContactModel model(std::uint64_t seq, const Vector3d& x) const {
    return contact(seq, x, force(x), S);  // K = -df/dx = S
  }
};

SpringTissue randomSpring(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Matrix3d A;
  for (int i = 0; i < 9; ++i) A(i) = u(rng);
  SpringTissue s;
  s.S = 300.0 * (A * A.transpose() + 0.2 * Matrix3d::Identity());
  s.rest = 0.01 * testutil::drawVector(u, rng);
  return s;
}

Vector3d randomVector(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return testutil::drawVector(u, rng);
}

ExtrapolatorOptions noBlend() {
  ExtrapolatorOptions o;
  o.blendTime = 0.0;
  return o;
}

// ---------------------------------------------------------------- extrapolation

TEST(ForceExtrapolator, SignOfStiffnessWithOneDimensionalSpring) {
  // Tissue surface at z = 0, tissue below; a spring of 400 N/m pushes the tool up (+z) by
  // 400 d. At z0 = -5 mm: f0 = +2 N, df/dz = -400, so K_zz = +400.
  const double k = 400.0;
  Matrix3d K = Matrix3d::Zero();
  K(2, 2) = k;
  ForceExtrapolator fx(noBlend());
  fx.submit(contact(1, Vector3d(0, 0, -0.005), Vector3d(0, 0, 2.0), K), 0.0, Vector3d::Zero());
  EXPECT_NEAR(fx.force(Vector3d(0, 0, -0.008), 0.001).z(), 3.2, 1e-14);  // deeper: pushes harder
  EXPECT_NEAR(fx.force(Vector3d(0, 0, -0.002), 0.001).z(), 0.8, 1e-14);  // shallower: softer
  EXPECT_NEAR(fx.force(Vector3d(0.01, 0.02, -0.005), 0.001).z(), 2.0, 1e-14);  // tangential: same
}

TEST(ForceExtrapolator, LinearSpringIsReproducedExactlyForAnyPosition) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const SpringTissue spring = randomSpring(rng);
    ForceExtrapolator fx(noBlend());
    fx.submit(spring.model(1, randomVector(rng, 0.02)), 0.0, Vector3d::Zero());
    for (int i = 0; i < 50; ++i) {
      const Vector3d x = randomVector(rng, i < 25 ? 0.02 : 1.0);  // near and far from x0
      const Vector3d exact = spring.force(x);
      EXPECT_LE((fx.force(x, 0.0) - exact).norm(), 1e-12 * (1.0 + exact.norm()));
    }
  }
}

TEST(ForceExtrapolator, BlendOfTwoModelsOfOneLinearSpringIsStillExact) {
  // Both models describe the same field from different anchor points, so every blend of
  // them, including one interrupted by a third model, must be that field.
  for (BlendMethod method : {BlendMethod::kFields, BlendMethod::kOffset}) {
    std::mt19937 rng(8);
    const SpringTissue spring = randomSpring(rng);
    ExtrapolatorOptions o;  // 15 ms smoothstep
    o.blendMethod = method;
    ForceExtrapolator fx(o);
    // Each tool position drawn before the model's anchor (g++'s order; random_draws.h).
    const auto submit = [&](int sequence, double stamp) {
      const Vector3d tool = randomVector(rng, 0.02);
      fx.submit(spring.model(sequence, randomVector(rng, 0.02)), stamp, tool);
    };
    submit(1, 0.0);
    submit(2, 0.100);
    submit(3, 0.107);  // mid-blend
    for (double t : {0.1, 0.104, 0.107, 0.110, 0.2}) {
      const Vector3d x = randomVector(rng, 0.05);
      const Vector3d exact = spring.force(x);
      EXPECT_LE((fx.force(x, t) - exact).norm(), 1e-12 * (1.0 + exact.norm())) << "t=" << t;
      EXPECT_LE((fx.field(t).at(x) - exact).norm(), 1e-12 * (1.0 + exact.norm())) << "t=" << t;
    }
  }
}

TEST(ForceExtrapolator, OffsetBlendUsesTheNewFieldPlusTheFadingJump) {
  // Old model: 2 N along z, K = 100 I at x0 = 0. New model: 1 N, K = 400 I at x0 = 0.
  // The device is at xs = (0, 0, -0.01) when the new model arrives, and moves on.
  ExtrapolatorOptions o;
  o.blendTime = 0.02;
  o.blendShape = BlendShape::kLinear;
  const Vector3d xs(0, 0, -0.01), x(0, 0, -0.02);
  const auto oldF = [](const Vector3d& p) { return Vector3d(Vector3d(0, 0, 2) - 100.0 * p); };
  const auto newF = [](const Vector3d& p) { return Vector3d(Vector3d(0, 0, 1) - 400.0 * p); };
  for (BlendMethod method : {BlendMethod::kFields, BlendMethod::kOffset}) {
    o.blendMethod = method;
    ForceExtrapolator fx(o);
    fx.submit(contact(1, Vector3d::Zero(), Vector3d(0, 0, 2), 100.0 * Matrix3d::Identity()), 0.0, xs);
    fx.submit(contact(2, Vector3d::Zero(), Vector3d(0, 0, 1), 400.0 * Matrix3d::Identity()), 1.0, xs);
    EXPECT_NEAR((fx.force(xs, 1.0) - oldF(xs)).norm(), 0.0, 1e-12);  // no jump at xs
    const Vector3d expected = method == BlendMethod::kOffset
                                  ? Vector3d(newF(x) + 0.5 * (oldF(xs) - newF(xs)))
                                  : Vector3d(0.5 * oldF(x) + 0.5 * newF(x));
    EXPECT_NEAR((fx.force(x, 1.01) - expected).norm(), 0.0, 1e-12);
    EXPECT_NEAR((fx.field(1.01).at(x) - expected).norm(), 0.0, 1e-12);
  }
  o.blendMethod = BlendMethod::kOffset;
  ForceExtrapolator fx(o);
  // A non-finite device position does not cost the model: the jump is taken at its x0.
  fx.submit(contact(1, Vector3d::Zero(), Vector3d(0, 0, 2), 100.0 * Matrix3d::Identity()), 0.0, xs);
  EXPECT_EQ(fx.submit(contact(2, Vector3d::Zero(), Vector3d(0, 0, 1), 400.0 * Matrix3d::Identity()), 1.0,
                      Vector3d(kNaN, 0, 0)),
            ModelVerdict::kAccepted);
  EXPECT_NEAR((fx.force(Vector3d::Zero(), 1.0) - oldF(Vector3d::Zero())).norm(), 0.0, 1e-12);
  EXPECT_TRUE(fx.force(x, 1.01).allFinite());
}

TEST(ForceExtrapolator, BlendWeightsLinearAndSmoothstep) {
  for (BlendShape shape : {BlendShape::kLinear, BlendShape::kSmoothstep}) {
    ExtrapolatorOptions o;
    o.blendTime = 0.02;
    o.blendShape = shape;
    ForceExtrapolator fx(o);
    fx.submit(contact(1, Vector3d::Zero(), Vector3d(1, 0, 0)), 0.0, Vector3d::Zero());
    fx.submit(contact(2, Vector3d::Zero(), Vector3d(3, 0, 0)), 1.0, Vector3d::Zero());
    const Vector3d x = Vector3d::Zero();
    const bool lin = shape == BlendShape::kLinear;
    EXPECT_NEAR(fx.force(x, 1.0).x(), 1.0, 1e-12);
    EXPECT_NEAR(fx.force(x, 1.005).x(), lin ? 1.5 : 1.0 + 2.0 * 0.15625, 1e-12);  // s = 1/4
    EXPECT_NEAR(fx.force(x, 1.010).x(), 2.0, 1e-12);
    EXPECT_NEAR(fx.force(x, 1.015).x(), lin ? 2.5 : 1.0 + 2.0 * 0.84375, 1e-12);  // s = 3/4
    EXPECT_NEAR(fx.force(x, 1.020).x(), 3.0, 1e-12);
    EXPECT_NEAR(fx.force(x, 5.0).x(), 3.0, 1e-12);
  }
}

TEST(ForceExtrapolator, FirstModelFadesInFromZero) {
  ExtrapolatorOptions o;
  o.blendTime = 0.01;
  o.blendShape = BlendShape::kLinear;
  ForceExtrapolator fx(o);
  EXPECT_EQ(fx.force(Vector3d::Zero(), 0.0), Vector3d::Zero());
  fx.submit(contact(1, Vector3d::Zero(), Vector3d(0, 0, 2)), 0.5, Vector3d::Zero());
  EXPECT_DOUBLE_EQ(fx.force(Vector3d::Zero(), 0.5).z(), 0.0);
  EXPECT_DOUBLE_EQ(fx.force(Vector3d::Zero(), 0.505).z(), 1.0);
  EXPECT_NEAR(fx.force(Vector3d::Zero(), 0.510).z(), 2.0, 1e-12);
}

TEST(ForceExtrapolator, ZeroOrderHoldIgnoresStiffnessAndPosition) {
  ExtrapolatorOptions o = noBlend();
  o.mode = ExtrapolationMode::kZeroOrderHold;
  ForceExtrapolator fx(o);
  fx.submit(contact(1, Vector3d(0, 0, -0.01), Vector3d(0, 0, 2), 500.0 * Matrix3d::Identity()), 0.0, Vector3d::Zero());
  EXPECT_EQ(fx.force(Vector3d(0.3, -0.2, -0.05), 0.001), Vector3d(0, 0, 2));
}

TEST(ForceExtrapolator, NoContactMeansZeroForceStillBlended) {
  ExtrapolatorOptions o;
  o.blendTime = 0.02;
  o.blendShape = BlendShape::kLinear;
  ForceExtrapolator fx(o);
  fx.submit(contact(1, Vector3d::Zero(), Vector3d(0, 0, 2), 100.0 * Matrix3d::Identity()), 0.0, Vector3d::Zero());
  // Out of contact: f0 and K are ignored even when they hold junk-but-finite numbers.
  fx.submit(contact(2, Vector3d::Zero(), Vector3d(9, 9, 9), 7.0 * Matrix3d::Identity(), false), 1.0, Vector3d::Zero());
  EXPECT_DOUBLE_EQ(fx.force(Vector3d::Zero(), 1.0).z(), 2.0);
  EXPECT_NEAR(fx.force(Vector3d::Zero(), 1.01).z(), 1.0, 1e-12);
  EXPECT_EQ(fx.force(Vector3d(0.1, 0.1, 0.1), 1.02), Vector3d::Zero());
}

TEST(ForceExtrapolator, MalformedModelsAreCountedAndTheOldOneKept) {
  ExtrapolatorOptions o = noBlend();
  o.maxStiffness = 1e5;
  ForceExtrapolator fx(o);
  const Matrix3d K = 200.0 * Matrix3d::Identity();
  ASSERT_EQ(fx.submit(contact(1, Vector3d::Zero(), Vector3d(0, 0, 1), K), 0.0, Vector3d::Zero()), ModelVerdict::kAccepted);
  std::vector<ContactModel> bad(6, contact(2, Vector3d::Zero(), Vector3d(0, 0, 4), K));
  bad[0].K(1, 2) = kNaN;
  bad[1].f0.x() = kInf;
  bad[2].x0.y() = -kInf;
  bad[3].stamp = kNaN;
  bad[4].simTime = kInf;
  bad[5].K(0, 0) = 2e5;  // finite but above maxStiffness
  for (const ContactModel& m : bad) EXPECT_EQ(fx.submit(m, 0.5, Vector3d::Zero()), ModelVerdict::kMalformed);
  EXPECT_EQ(fx.submit(contact(2, Vector3d::Zero(), Vector3d(0, 0, 4), K), kNaN, Vector3d::Zero()), ModelVerdict::kMalformed);
  EXPECT_EQ(fx.counters().malformed, 7u);
  EXPECT_EQ(fx.counters().accepted, 1u);
  EXPECT_DOUBLE_EQ(fx.force(Vector3d::Zero(), 0.6).z(), 1.0);
  EXPECT_DOUBLE_EQ(fx.modelAge(0.6), 0.6);  // a rejected model does not feed the watchdog
  // The same sequence number, well formed, is still welcome.
  EXPECT_EQ(fx.submit(contact(2, Vector3d::Zero(), Vector3d(0, 0, 4), K), 0.7, Vector3d::Zero()), ModelVerdict::kAccepted);
  EXPECT_DOUBLE_EQ(fx.force(Vector3d::Zero(), 0.7).z(), 4.0);
}

TEST(ForceExtrapolator, OutOfOrderAndDuplicateSequencesAreDropped) {
  ForceExtrapolator fx(noBlend());
  EXPECT_EQ(fx.submit(contact(10, Vector3d::Zero(), Vector3d(0, 0, 1)), 0.0, Vector3d::Zero()), ModelVerdict::kAccepted);
  EXPECT_EQ(fx.submit(contact(10, Vector3d::Zero(), Vector3d(0, 0, 2)), 0.1, Vector3d::Zero()), ModelVerdict::kStaleSequence);
  EXPECT_EQ(fx.submit(contact(9, Vector3d::Zero(), Vector3d(0, 0, 3)), 0.2, Vector3d::Zero()), ModelVerdict::kStaleSequence);
  EXPECT_DOUBLE_EQ(fx.force(Vector3d::Zero(), 0.3).z(), 1.0);
  EXPECT_DOUBLE_EQ(fx.modelAge(0.3), 0.3);
  EXPECT_EQ(fx.submit(contact(13, Vector3d::Zero(), Vector3d(0, 0, 5)), 0.4, Vector3d::Zero()), ModelVerdict::kAccepted);
  EXPECT_DOUBLE_EQ(fx.force(Vector3d::Zero(), 0.4).z(), 5.0);
  EXPECT_EQ(fx.counters().staleSequence, 2u);
  EXPECT_EQ(fx.counters().accepted, 2u);
  fx.reset();  // a restarted simulation starts its sequence again
  EXPECT_EQ(fx.modelAge(0.5), kInf);
  EXPECT_EQ(fx.submit(contact(1, Vector3d::Zero(), Vector3d(0, 0, 1)), 0.5, Vector3d::Zero()), ModelVerdict::kAccepted);
}

// A simulation that restarts sends sequences from 1 again: after restartAfterStale of them in
// a row the extrapolator starts over with the last one (fading in from zero); fewer, or a
// newer sequence in between, keep the old model.
TEST(ForceExtrapolator, RestartsAfterStaleModelsInARow) {
  ExtrapolatorOptions o = noBlend();
  o.restartAfterStale = 3;
  ForceExtrapolator fx(o);
  EXPECT_EQ(fx.submit(contact(100, Vector3d::Zero(), Vector3d(0, 0, 1)), 0.0, Vector3d::Zero()), ModelVerdict::kAccepted);
  EXPECT_EQ(fx.submit(contact(1, Vector3d::Zero(), Vector3d(0, 0, 2)), 0.1, Vector3d::Zero()), ModelVerdict::kStaleSequence);
  EXPECT_EQ(fx.submit(contact(2, Vector3d::Zero(), Vector3d(0, 0, 2)), 0.2, Vector3d::Zero()), ModelVerdict::kStaleSequence);
  EXPECT_EQ(fx.submit(contact(101, Vector3d::Zero(), Vector3d(0, 0, 3)), 0.3, Vector3d::Zero()), ModelVerdict::kAccepted);
  EXPECT_EQ(fx.counters().restarts, 0u);
  EXPECT_EQ(fx.submit(contact(1, Vector3d::Zero(), Vector3d(0, 0, 7)), 0.4, Vector3d::Zero()), ModelVerdict::kStaleSequence);
  EXPECT_EQ(fx.submit(contact(2, Vector3d::Zero(), Vector3d(0, 0, 7)), 0.5, Vector3d::Zero()), ModelVerdict::kStaleSequence);
  EXPECT_DOUBLE_EQ(fx.force(Vector3d::Zero(), 0.5).z(), 3.0);
  EXPECT_EQ(fx.submit(contact(3, Vector3d::Zero(), Vector3d(0, 0, 7)), 0.6, Vector3d::Zero()), ModelVerdict::kAccepted);
  EXPECT_EQ(fx.counters().restarts, 1u);
  EXPECT_EQ(fx.counters().staleSequence, 5u);
  EXPECT_DOUBLE_EQ(fx.force(Vector3d::Zero(), 0.6).z(), 7.0);
  EXPECT_EQ(fx.submit(contact(4, Vector3d::Zero(), Vector3d(0, 0, 8)), 0.7, Vector3d::Zero()), ModelVerdict::kAccepted);

  // With blending, the restarted model fades in from zero (it does not jump from the old one).
  ExtrapolatorOptions blended;
  blended.restartAfterStale = 2;
  ForceExtrapolator fade(blended);
  fade.submit(contact(50, Vector3d::Zero(), Vector3d(0, 0, 4)), 0.0, Vector3d::Zero());
  EXPECT_DOUBLE_EQ(fade.force(Vector3d::Zero(), 1.0).z(), 4.0);
  fade.submit(contact(1, Vector3d::Zero(), Vector3d(0, 0, 2)), 1.0, Vector3d::Zero());
  EXPECT_EQ(fade.submit(contact(2, Vector3d::Zero(), Vector3d(0, 0, 2)), 1.1, Vector3d::Zero()), ModelVerdict::kAccepted);
  EXPECT_DOUBLE_EQ(fade.force(Vector3d::Zero(), 1.1).z(), 0.0);
  EXPECT_GT(fade.force(Vector3d::Zero(), 1.1 + 0.5 * blended.blendTime).z(), 0.0);
  EXPECT_LT(fade.force(Vector3d::Zero(), 1.1 + 0.5 * blended.blendTime).z(), 2.0);
  EXPECT_DOUBLE_EQ(fade.force(Vector3d::Zero(), 1.1 + blended.blendTime).z(), 2.0);

  o.restartAfterStale = 0;  // never
  ForceExtrapolator never(o);
  never.submit(contact(100, Vector3d::Zero(), Vector3d(0, 0, 1)), 0.0, Vector3d::Zero());
  for (int i = 1; i <= 20; ++i)
    EXPECT_EQ(never.submit(contact(i, Vector3d::Zero(), Vector3d(0, 0, 2)), 0.01 * i, Vector3d::Zero()), ModelVerdict::kStaleSequence);
  EXPECT_EQ(never.counters().restarts, 0u);
}

TEST(ForceExtrapolator, InvalidOptionsThrow) {
  ExtrapolatorOptions o;
  o.blendTime = -0.01;
  EXPECT_THROW(ForceExtrapolator{o}, std::invalid_argument);
  o.blendTime = kNaN;
  EXPECT_THROW(ForceExtrapolator{o}, std::invalid_argument);
  o = ExtrapolatorOptions();
  o.maxStiffness = 0.0;
  EXPECT_THROW(ForceExtrapolator{o}, std::invalid_argument);
  o = ExtrapolatorOptions();
  o.restartAfterStale = -1;
  EXPECT_THROW(ForceExtrapolator{o}, std::invalid_argument);
}

// Largest output change between 1 kHz ticks while random models (force at the origin up to
// fmax, K = k I with k up to kMax, x0 within 1 cm) arrive at random intervals of 1 to 40 ms,
// some mid-blend, and the device moves as amplitude * (sin, cos, sin)(2 pi t) about the origin.
constexpr double kMax = 500.0;
double largestStepUnderAbruptModels(const ExtrapolatorOptions& o, double fmax, double amplitude,
                                    unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> gap(0.001, 0.040), unit(0.0, 1.0);
  ForceExtrapolator fx(o);
  double nextArrival = 0.0, largest = 0.0;
  std::uint64_t seq = 0;
  Vector3d previous = Vector3d::Zero();
  for (int i = 0; i < 20000; ++i) {
    const double t = 1e-3 * i;
    const double phase = 2.0 * M_PI * t;
    const Vector3d x = amplitude * Vector3d(std::sin(phase), std::cos(phase), std::sin(phase));
    while (nextArrival <= t) {
      const Vector3d x0 = randomVector(rng, 0.01);
      const Matrix3d K = kMax * unit(rng) * Matrix3d::Identity();
      Vector3d atOrigin = randomVector(rng, 1.0);
      atOrigin *= fmax * std::sqrt(unit(rng)) / atOrigin.norm();
      fx.submit(contact(++seq, x0, atOrigin - K * x0, K, unit(rng) > 0.1), t, x);
      nextArrival += gap(rng);
    }
    const Vector3d out = fx.force(x, t);
    if (i > 0) largest = std::max(largest, (out - previous).norm());
    previous = out;
  }
  return largest;
}

TEST(ForceExtrapolator, BlendingKeepsAbruptModelChangesWithinTheRateLimit) {
  // Device at rest: any two forces differ by at most 2 fmax and the blend weight moves at
  // most 1.5 dt / T per tick (smoothstep; 1 for linear), so a tick step is at most
  // 3 fmax dt / T: 1 N with fmax = 5 N, T = 15 ms, what SafetyOptions' 1000 N/s allows per ms.
  const double fmax = 5.0, dt = 1e-3;
  const double rateLimitStep = SafetyOptions().maxForceRate * dt;
  for (BlendMethod method : {BlendMethod::kFields, BlendMethod::kOffset}) {
    ExtrapolatorOptions smooth;  // 15 ms smoothstep
    smooth.blendMethod = method;
    ExtrapolatorOptions linear = smooth;
    linear.blendShape = BlendShape::kLinear;
    for (unsigned seed : {1u, 2u, 3u}) {
      const double stepSmooth = largestStepUnderAbruptModels(smooth, fmax, 0.0, seed);
      const double stepLinear = largestStepUnderAbruptModels(linear, fmax, 0.0, seed);
      EXPECT_LE(stepSmooth, 3.0 * fmax * dt / smooth.blendTime + 1e-12);
      EXPECT_LE(stepLinear, 2.0 * fmax * dt / linear.blendTime + 1e-12);
      EXPECT_LE(stepSmooth, rateLimitStep + 1e-12);
      // Without the blend the same models make steps of several newtons.
      EXPECT_GT(largestStepUnderAbruptModels(noBlend(), fmax, 0.0, seed), 3.0 * rateLimitStep);

      // Device moving (2 mm, 1 Hz): the fields now span 2 R with R = fmax + kMax |x|max, the
      // offset method's remembered force may be off by kMax times the travel in a blend,
      // and the device's own motion adds kMax |dx| per tick.
      const double amp = 0.002, xMax = std::sqrt(3.0) * amp, dxMax = 2.0 * M_PI * xMax * dt;
      const double R = fmax + kMax * xMax;
      const double bound = 1.5 * dt / smooth.blendTime * (2.0 * R + 2.0 * kMax * xMax) + kMax * dxMax;
      EXPECT_LE(largestStepUnderAbruptModels(smooth, fmax, amp, seed), bound);
      EXPECT_GT(largestStepUnderAbruptModels(noBlend(), fmax, amp, seed), 2.0 * bound);
    }
  }
}

WallProbe testProbe() {
  WallProbe p;
  p.wall.normal = Vector3d(0.2, -0.1, 1.0).normalized();
  p.wall.k = 200.0;
  p.wall.k3 = 1e6;
  p.center = Vector3d(0.0, 0.0, -0.007);  // always 2 to 11 mm deep
  p.a = Vector3d(0.0, 0.0, 0.004);
  p.b = Vector3d(0.003, 0.002, 0.0);
  p.frequency = 2.0;  // about 6 cm/s
  p.simPeriod = 0.02;
  p.latency = 0.005;
  p.duration = 3.0;
  return p;
}

TEST(WallProbe, ModelIsTheExactForceAndMinusItsDerivative) {
  const WallProbe p = testProbe();
  const Vector3d x(0.001, -0.002, -0.006);
  const ContactModel m = p.wall.model(x, 1, 0.0);
  ASSERT_TRUE(m.inContact);
  const double d = p.wall.penetration(x);
  EXPECT_NEAR(m.f0.norm(), p.wall.k * d + p.wall.k3 * d * d * d, 1e-14);
  Matrix3d fd;
  const double h = 1e-7;
  for (int j = 0; j < 3; ++j) {
    const Vector3d e = h * Vector3d::Unit(j);
    fd.col(j) = -(p.wall.force(x + e) - p.wall.force(x - e)) / (2 * h);
  }
  EXPECT_LT((fd - m.K).norm(), 1e-6 * m.K.norm());
  EXPECT_FALSE(p.wall.model(Vector3d(0, 0, 0.001), 2, 0.0).inContact);
}

TEST(WallProbe, LinearExtrapolationBeatsZeroOrderHoldOnANonlinearWall) {
  const WallProbe probe = testProbe();
  ExtrapolatorOptions zoh = noBlend();
  zoh.mode = ExtrapolationMode::kZeroOrderHold;
  const ForceErrorStats hold = measureExtrapolationError(probe, zoh);
  const ForceErrorStats linear = measureExtrapolationError(probe, noBlend());
  const ForceErrorStats blended = measureExtrapolationError(probe, ExtrapolatorOptions());
  ExtrapolatorOptions fieldsOptions;
  fieldsOptions.blendMethod = BlendMethod::kFields;
  const ForceErrorStats fields = measureExtrapolationError(probe, fieldsOptions);
  // The scenario must actually be hard for the hold: errors of several percent of the force.
  EXPECT_GT(hold.rms, 0.05 * hold.rmsForce);
  EXPECT_LT(linear.rms, 0.3 * hold.rms);
  EXPECT_LT(blended.rms, 0.3 * hold.rms);
  EXPECT_LT(linear.max, 0.3 * hold.max);
  EXPECT_LT(fields.rms, 0.3 * hold.rms);
  // The blend smooths the steps at model arrivals; fading the offset lags less than
  // blending the fields, at the same smoothing.
  EXPECT_LT(blended.maxStep, 0.7 * linear.maxStep);
  EXPECT_LT(blended.rms, fields.rms);
  EXPECT_LT(std::abs(blended.maxStep - fields.maxStep), 0.1 * fields.maxStep);
}

TEST(WallProbe, MeasuredOrdersInTheSimulationPeriod) {
  // Without latency or blend, the hold's error is first order in the device travel over one
  // simulation period and the linear extrapolation's is second order.
  WallProbe probe = testProbe();
  probe.latency = 0.0;
  ExtrapolatorOptions zoh = noBlend();
  zoh.mode = ExtrapolationMode::kZeroOrderHold;
  auto rms = [&](const ExtrapolatorOptions& o, double period) {
    probe.simPeriod = period;
    return measureExtrapolationError(probe, o).rms;
  };
  const double orderHold = std::log2(rms(zoh, 0.02) / rms(zoh, 0.01));
  const double orderLinear = std::log2(rms(noBlend(), 0.02) / rms(noBlend(), 0.01));
  EXPECT_NEAR(orderHold, 1.0, 0.2);
  EXPECT_NEAR(orderLinear, 2.0, 0.3);
}

// ---------------------------------------------------------------- safety filter

TEST(SafetyFilter, ClampMagnitudeKeepsDirectionAndSurvivesHugeValues) {
  EXPECT_EQ(clampMagnitude(Vector3d(1, 2, 2), 5.0), Vector3d(1, 2, 2));
  const Vector3d c = clampMagnitude(Vector3d(30, 0, -40), 5.0);
  EXPECT_NEAR((c - Vector3d(3, 0, -4)).norm(), 0.0, 1e-15);
  const double big = std::numeric_limits<double>::max();
  const Vector3d h = clampMagnitude(Vector3d(big, -big, big), 2.0);
  ASSERT_TRUE(h.allFinite());
  EXPECT_NEAR((h - Vector3d(2, -2, 2) / std::sqrt(3.0)).norm(), 0.0, 1e-15);
  EXPECT_EQ(clampMagnitude(Vector3d(1, 1, 1), 0.0), Vector3d::Zero());
}

TEST(SafetyFilter, InvalidOptionsThrow) {
  SafetyOptions o;
  o.fadeTime = 0.06;
  EXPECT_THROW(SafetyFilter{o}, std::invalid_argument);
  o = SafetyOptions();
  o.maxForceRate = 100.0;  // 100 N/s * 30 ms < 5 N: the fade could not obey the rate limit
  EXPECT_THROW(SafetyFilter{o}, std::invalid_argument);
  o = SafetyOptions();
  o.modelTimeout = kNaN;
  EXPECT_THROW(SafetyFilter{o}, std::invalid_argument);
}

// Runs the filter at 1 kHz from tick `from` to `to` with a fresh model and `enabled`.
Vector3d run(SafetyFilter& f, int from, int to, const Vector3d& request, bool enabled = true) {
  Vector3d out = f.output();
  for (int i = from; i < to; ++i) out = f.step(request, 1e-3 * i, 0.0, enabled);
  return out;
}

TEST(SafetyFilter, StartsAtZeroAndClampsMagnitudeKeepingDirection) {
  SafetyFilter f;  // 5 N, 1000 N/s
  EXPECT_EQ(f.step(Vector3d(30, 0, 40), 0.0, 0.0, true), Vector3d::Zero());
  const Vector3d out = run(f, 1, 500, Vector3d(30, 0, 40));
  EXPECT_NEAR((out - Vector3d(3, 0, 4)).norm(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(f.gain(), 1.0);
  EXPECT_GT(f.counters().forceClamped, 0u);
}

TEST(SafetyFilter, RateLimitIsExactPerTick) {
  SafetyFilter f;
  run(f, 0, 200, Vector3d::Zero());
  ASSERT_DOUBLE_EQ(f.gain(), 1.0);
  for (int i = 200; i < 204; ++i) {
    const Vector3d out = f.step(Vector3d(0, 0, 3.5), 1e-3 * i, 0.0, true);
    EXPECT_NEAR(out.z(), std::min(3.5, 1.0 * (i - 199)), 1e-12);  // 1000 N/s * 1 ms
  }
  const Vector3d out = f.step(Vector3d(0, 0, -3.5), 0.204, 0.0, true);
  EXPECT_NEAR(out.z(), 2.5, 1e-12);
}

TEST(SafetyFilter, NonFiniteInputFadesTheLastOutputToZero) {
  SafetyOptions o;
  o.fadeTime = 0.02;  // shrink 5 N / 20 ms = 0.25 N per tick
  SafetyFilter f(o);
  run(f, 0, 300, Vector3d(0, 2, 0));
  ASSERT_NEAR(f.output().y(), 2.0, 1e-12);
  const Vector3d bad[] = {Vector3d(kNaN, 0, 0), Vector3d(0, kInf, 0), Vector3d(-kInf, kNaN, 1)};
  for (int i = 300; i < 309; ++i) {
    const Vector3d out = f.step(bad[i % 3], 1e-3 * i, 0.0, true);
    ASSERT_TRUE(out.allFinite());
    EXPECT_NEAR(out.y(), std::max(0.0, 2.0 - 0.25 * (i - 299)), 1e-12);
  }
  EXPECT_EQ(f.output(), Vector3d::Zero());
  EXPECT_EQ(f.counters().nonFiniteInputs, 9u);
  // A good input again: the force comes back under the rate limit.
  EXPECT_NEAR(f.step(Vector3d(0, 2, 0), 0.309, 0.0, true).y(), 1.0, 1e-12);
}

TEST(SafetyFilter, WatchdogFadesToExactlyZeroWithinFadeTime) {
  SafetyOptions o;
  o.modelTimeout = 0.05;
  o.fadeTime = 0.02;
  SafetyFilter f(o);
  const double lastModel = 0.3;  // the model stops arriving
  int firstStale = -1;
  for (int i = 0; i < 600; ++i) {
    const double t = 1e-3 * i;
    const double age = t < lastModel ? 0.0 : t - lastModel;
    const Vector3d out = f.step(Vector3d(0, 0, 4), t, age, true);
    if (age > o.modelTimeout && firstStale < 0) {
      firstStale = i;
      EXPECT_GT(out.norm(), 3.0);  // a fade, not a cut
    }
    if (firstStale >= 0 && t >= 1e-3 * firstStale + o.fadeTime) EXPECT_EQ(out, Vector3d::Zero()) << i;
    if (firstStale < 0 && i > 200) EXPECT_NEAR(out.z(), 4.0, 1e-12);
  }
  EXPECT_TRUE(f.watchdogTripped());
  EXPECT_EQ(f.counters().watchdogTrips, 1u);
  // The simulation is back: the force returns, gradually.
  Vector3d out = f.step(Vector3d(0, 0, 4), 0.600, 0.0, true);
  EXPECT_GT(out.z(), 0.0);
  EXPECT_LT(out.z(), 0.1);
  out = run(f, 601, 800, Vector3d(0, 0, 4));
  EXPECT_NEAR(out.z(), 4.0, 1e-12);
}

TEST(SafetyFilter, DisableFadesToZeroWithinFadeTimeAndStaysZero) {
  SafetyFilter f;  // fade 30 ms
  run(f, 0, 300, Vector3d(-5, 0, 0));
  ASSERT_NEAR(f.output().x(), -5.0, 1e-12);
  for (int i = 300; i < 400; ++i) {
    const Vector3d out = f.step(Vector3d(-5, 0, 0), 1e-3 * i, 0.0, false);
    if (i >= 330) EXPECT_EQ(out, Vector3d::Zero()) << i;
    if (i < 329) EXPECT_LT(out.x(), 0.0) << i;
  }
  EXPECT_NEAR(run(f, 400, 700, Vector3d(-5, 0, 0)).x(), -5.0, 1e-12);
}

TEST(SafetyFilter, UnusableClockCountsAndFades) {
  SafetyFilter f;
  run(f, 0, 300, Vector3d(0, 0, 3));
  for (int i = 0; i < 40; ++i) {
    const double t = i % 2 ? kNaN : 0.1;  // NaN, or a time far in the past
    const Vector3d out = f.step(Vector3d(0, 0, 3), t, 0.0, true);
    ASSERT_TRUE(out.allFinite());
  }
  EXPECT_EQ(f.output(), Vector3d::Zero());
  EXPECT_GE(f.counters().timeFaults, 39u);
}

struct PropertyBounds {
  double maxNorm = 0.0, maxRateExcess = -kInf;
  int zeroViolations = 0, zeroChecks = 0;
};

// Random requests (ordinary, huge, NaN, Inf, tiny), random model arrivals and silences,
// random enable toggles and jittered tick lengths; checks every tick against the guarantees.
PropertyBounds runSafetyProperty(const SafetyOptions& o, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SafetyFilter f(o);
  PropertyBounds b;
  double t = 0.0, lastModel = -kInf, nextModel = 0.0, nextToggle = 0.0;
  bool enabled = true, hadTick = false;
  double badSince = kInf;  // first tick of the current stale-or-disabled stretch
  Vector3d request = Vector3d::Zero(), previous = Vector3d::Zero();
  for (int i = 0; i < 40000; ++i) {
    const double tPrevious = t;
    t += 2e-4 + 2.8e-3 * unit(rng);
    const double dt = t - tPrevious;  // the tick length the filter sees
    if (t >= nextModel) {  // a model now, then a short gap or a long silence
      lastModel = t;
      nextModel = t + (unit(rng) < 0.97 ? 0.02 * unit(rng) : 0.4 * unit(rng));
    }
    if (t >= nextToggle) {
      enabled = unit(rng) < 0.8;
      nextToggle = t + 0.3 * unit(rng);
    }
    const double kind = unit(rng);
    Vector3d in;
    if (kind < 0.02) in = Vector3d(kNaN, 0, 1);
    else if (kind < 0.04) in = Vector3d(1, -kInf, 0);
    else if (kind < 0.06) in = Vector3d(1e300, -1e308, 1e-300);
    else if (kind < 0.08) in = Vector3d(4e-320, 0, 0);
    else if (kind < 0.3) in = request = randomVector(rng, 20.0);  // a jump
    else in = request += randomVector(rng, 0.05);                  // drift
    const double age = unit(rng) < 0.01 ? kNaN : t - lastModel;
    const Vector3d out = f.step(in, t, age, enabled);

    if (!out.allFinite()) {
      b.maxNorm = kInf;
      return b;
    }
    b.maxNorm = std::max(b.maxNorm, out.norm());
    if (hadTick) b.maxRateExcess = std::max(b.maxRateExcess, (out - previous).norm() - o.maxForceRate * dt);
    const bool bad = !enabled || !(age <= o.modelTimeout);
    if (!bad) badSince = kInf;
    else if (badSince == kInf) badSince = t;
    if (t >= badSince + o.fadeTime) {
      ++b.zeroChecks;
      if (out != Vector3d::Zero()) ++b.zeroViolations;
    }
    previous = out;
    hadTick = true;
  }
  return b;
}

TEST(SafetyFilter, RandomizedInputsNeverBreakTheGuarantees) {
  SafetyOptions tight;
  tight.maxForce = 4.0;
  tight.maxForceRate = 200.0;  // the tightest rate the fade allows: 4 N / 20 ms
  tight.fadeTime = 0.02;
  tight.modelTimeout = 0.05;
  tight.resumeTime = 0.05;
  for (const SafetyOptions& o : {SafetyOptions(), tight}) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      const PropertyBounds b = runSafetyProperty(o, seed);
      EXPECT_LE(b.maxNorm, o.maxForce * (1.0 + 1e-12)) << seed;
      EXPECT_LE(b.maxRateExcess, 1e-12) << seed;
      EXPECT_GT(b.zeroChecks, 1000) << seed;  // the scenario does trip the watchdog
      EXPECT_EQ(b.zeroViolations, 0) << seed;
      EXPECT_GT(b.maxNorm, 0.5 * o.maxForce) << seed;  // and does pass force through
    }
  }
}

// ---------------------------------------------------------------- pipeline and loop statistics

TEST(HapticPipeline, SpringContactReachesTheDeviceAfterStartUp) {
  std::mt19937 rng(5);
  SpringTissue spring = randomSpring(rng);
  spring.S /= 10.0;  // keep the force under the 5 N limit over the path
  HapticPipeline pipeline;
  std::uint64_t seq = 0;
  double worst = 0.0;
  for (int i = 0; i < 1000; ++i) {
    const double t = 1e-3 * i;
    const Vector3d x = 0.01 * Vector3d(std::sin(3 * t), std::cos(2 * t), 0.5 * std::sin(t));
    if (i % 20 == 0) pipeline.submit(spring.model(++seq, x), t, x);
    const Vector3d out = pipeline.tick(x, t, true);
    if (t > 0.2) worst = std::max(worst, (out - spring.force(x)).norm());
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(pipeline.loopStats().totalTicks(), 1000u);
  EXPECT_EQ(pipeline.extrapolator().counters().accepted, 50u);
}

TEST(LoopStats, RatePercentilesAndOverrunsFromTickTimes) {
  std::vector<double> periods(98, 1e-3);
  periods.push_back(1.2e-3);
  periods.push_back(5e-3);
  std::mt19937 rng(3);
  std::shuffle(periods.begin(), periods.end(), rng);
  std::vector<double> times = {10.0};
  for (double p : periods) times.push_back(times.back() + p);
  const LoopStats s = computeLoopStats(times, 1.5e-3);
  EXPECT_EQ(s.ticks, 101u);
  EXPECT_NEAR(s.rate, 100.0 / (0.098 + 0.0012 + 0.005), 1e-6);
  EXPECT_NEAR(s.periodP50, 1e-3, 1e-11);
  EXPECT_NEAR(s.periodP99, 1.2e-3, 1e-11);  // the 99th of 100 sorted periods
  EXPECT_NEAR(s.periodMax, 5e-3, 1e-11);
  EXPECT_EQ(s.overruns, 1u);
  EXPECT_EQ(computeLoopStats({1.0}, 1e-3).rate, 0.0);
}

TEST(LoopStats, NearestRankPercentile) {
  std::vector<double> v = {5, 1, 4, 2, 3};
  EXPECT_EQ(nearestRankPercentile(v, 0.5), 3.0);
  EXPECT_EQ(nearestRankPercentile(v, 0.0), 1.0);
  EXPECT_EQ(nearestRankPercentile(v, 0.99), 5.0);
  EXPECT_EQ(nearestRankPercentile(v, 0.2), 1.0);
  EXPECT_EQ(nearestRankPercentile(v, 0.21), 2.0);
}

TEST(LoopStats, WindowSummarisesTheLastTicksAndCountsEveryOverrun) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> jitter(0.8e-3, 1.8e-3);
  LoopStatsWindow window(64, 1.5e-3);
  std::vector<double> all;
  double t = 0.0;
  std::uint64_t overruns = 0;
  for (int i = 0; i < 300; ++i) {
    const double p = jitter(rng);
    if (i > 0 && p > 1.5e-3) ++overruns;
    t += i > 0 ? p : 0.0;
    all.push_back(t);
    window.record(t);
    if (i == 10 || i == 299) {
      const std::vector<double> last(all.end() - std::min<std::ptrdiff_t>(64, all.size()), all.end());
      const LoopStats a = window.summary(), b = computeLoopStats(last, 1.5e-3);
      EXPECT_EQ(a.ticks, b.ticks);
      EXPECT_EQ(a.overruns, b.overruns);
      EXPECT_DOUBLE_EQ(a.rate, b.rate);
      EXPECT_DOUBLE_EQ(a.periodP50, b.periodP50);
      EXPECT_DOUBLE_EQ(a.periodP99, b.periodP99);
      EXPECT_DOUBLE_EQ(a.periodMax, b.periodMax);
    }
  }
  EXPECT_EQ(window.totalOverruns(), overruns);
  EXPECT_EQ(window.totalTicks(), 300u);
}

}  // namespace
}  // namespace tt
