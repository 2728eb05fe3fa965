// The step-size controllers and the shared frame loop, driven by methods defined here: an
// embedded Heun/Euler pair (order 2 with an order-1 error estimate) and a scripted method
// whose attempts report what a test asks for. A method from outside the integrators' own files
// plugs into the loop this way.
#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "oscillators.h"
#include "tissue_trainer/core/integrate/step_control.h"
#include "tissue_trainer/core/integrate/stepped_integrator.h"

namespace tt {
namespace {

using namespace oscillators;

// Heun's method with forward Euler as the embedded estimate: weighted RMS of their difference.
class HeunEuler : public SteppedIntegrator {
 public:
  HeunEuler(std::unique_ptr<StepSizeController> control, double tol)
      : SteppedIntegrator(std::move(control)), tol_(tol) {}
  const char* name() const override { return "heun_euler"; }
  std::vector<double> keptSteps;

 private:
  FrameStart beginFrame(System&, double) override { return {}; }
  StepAttempt attempt(System& system, const StepContext& step, StepReport&) override {
    const State& s = system.state;
    const double h = step.h;
    system.computeForce(s.x, s.v, f_);
    const Eigen::VectorXd a1 = f_.cwiseQuotient(system.mass);
    const Eigen::VectorXd xe = s.x + h * s.v, ve = s.v + h * a1;
    system.computeForce(xe, ve, f_);
    const Eigen::VectorXd a2 = f_.cwiseQuotient(system.mass);
    x1_ = s.x + 0.5 * h * (s.v + ve);
    v1_ = s.v + 0.5 * h * (a1 + a2);
    double sum = 0.0;
    for (Eigen::Index i = 0; i < x1_.size(); ++i) {
      sum += std::pow((x1_[i] - xe[i]) / (tol_ * (1.0 + std::abs(x1_[i]))), 2);
      sum += std::pow((v1_[i] - ve[i]) / (tol_ * (1.0 + std::abs(v1_[i]))), 2);
    }
    StepAttempt out;
    out.measure.error = std::sqrt(sum / (2.0 * x1_.size()));
    return out;
  }
  std::string accept(System& system, const StepContext& step) override {
    system.state.x = x1_;
    system.state.v = v1_;
    system.state.t = step.end;
    keptSteps.push_back(step.h);
    return "";
  }
  double tol_;
  Eigen::VectorXd f_, x1_, v1_;
};

ErrorStepParams heunParams(double initialStep) {
  ErrorStepParams p;
  p.estimatorOrder = 1;
  p.initialStep = initialStep;
  p.holdBelowGrowth = 1.0;
  return p;
}

struct HeunRun {
  double error = 0.0;
  int kept = 0, rejected = 0;
};

// One second of the harmonic oscillators (period 1 s) in frames of 0.1 s.
HeunRun runHeun(HeunEuler& method, const Oscillators& o) {
  System s = o.build();
  HeunRun run;
  for (int frame = 0; frame < 10; ++frame) {
    const StepReport r = method.advance(s, 0.1);
    EXPECT_TRUE(r.ok) << r.failure;
    EXPECT_NEAR(s.state.t, 0.1 * (frame + 1), 1e-15) << "a frame must end at its end";
    run.kept += r.substeps;
    run.rejected += r.rejected;
  }
  run.error = o.maxError(s);
  return run;
}

TEST(ErrorStepControl, HeunEulerPairFollowsItsToleranceAtTheExpectedCost) {
  const Oscillators o = harmonic(0.0);
  std::vector<HeunRun> runs;
  for (double tol : {1e-3, 1e-5}) {
    HeunEuler method(std::make_unique<ErrorStepControl>(heunParams(0.05)), tol);
    runs.push_back(runHeun(method, o));
    EXPECT_LT(runs.back().error, 30.0 * tol) << "tol " << tol;
  }
  // Local error ~ h^2 held at tol: the steps shrink like tol^(1/2), 10x for 100x tolerance.
  const double stepRatio = static_cast<double>(runs[1].kept) / runs[0].kept;
  EXPECT_GT(stepRatio, 6.0);
  EXPECT_LT(stepRatio, 16.0);
  EXPECT_LT(runs[1].error, runs[0].error / 30.0);
  EXPECT_GT(runs[0].rejected, 0) << "a first step of 0.05 s at 1e-3 must be rejected";
}

// The number of steps that grew, after checking that every kept step (but a frame's last, cut
// to the frame's end) is initialStep * 2^k.
int doublingsOnAPowerOfTwoLadder(const std::vector<double>& steps, double initialStep) {
  int doublings = 0;
  for (size_t i = 0; i < steps.size(); ++i) {
    const double k = std::log2(steps[i] / initialStep);
    EXPECT_NEAR(k, std::round(k), 1e-9) << "step " << i << " is not initial * 2^k";
    if (i > 0 && steps[i] > steps[i - 1]) ++doublings;
  }
  return doublings;
}

TEST(HalvingDoublingControl, ErrorThresholdsKeepEveryStepWithinTheUpperLimit) {
  // The Adams-Bashforth-Moulton control of the Adamss chapter (Sec. 2.5.4): halve and redo
  // above the upper error, double at or below the lower one. From a step too short it doubles
  // up to the band; from one too long it halves down to it.
  HalvingDoublingParams p;
  p.quantity = HalvingDoublingParams::Quantity::kError;
  p.lower = 0.1;
  p.upper = 1.0;
  for (double initial : {0.1 / 64, 0.1 / 2}) {
    p.initialStep = initial;
    HeunEuler method(std::make_unique<HalvingDoublingControl>(p), 1e-4);
    const HeunRun run = runHeun(method, harmonic(0.0));
    EXPECT_LT(run.error, 30.0 * 1e-4);
    const int doublings = doublingsOnAPowerOfTwoLadder(method.keptSteps, initial);
    if (initial < 0.01) {
      EXPECT_GT(doublings, 0);
    } else {
      EXPECT_GT(run.rejected, 0);
    }
  }
}

// A method whose attempts return the next scripted outcome (or converge with no measure).
class Scripted : public SteppedIntegrator {
 public:
  explicit Scripted(std::unique_ptr<StepSizeController> control, long maxAttempts = 100000)
      : SteppedIntegrator(std::move(control), maxAttempts) {}
  const char* name() const override { return "scripted"; }
  std::deque<StepAttempt> script;
  std::function<StepAttempt(const StepContext&)> rule;  // after the script
  std::vector<StepContext> attempts;
  int abandoned = 0;

 private:
  FrameStart beginFrame(System&, double) override { return {}; }
  StepAttempt attempt(System&, const StepContext& step, StepReport&) override {
    attempts.push_back(step);
    if (script.empty()) return rule ? rule(step) : StepAttempt{};
    StepAttempt next = script.front();
    script.pop_front();
    return next;
  }
  std::string accept(System& system, const StepContext& step) override {
    system.state.x.array() += 1.0;
    system.state.t = step.end;
    return "";
  }
  void abandonFrame(const System&) override { ++abandoned; }
};

StepAttempt notConverged(double factor) {
  StepAttempt a;
  a.status = StepStatus::kNotConverged;
  a.retryFactor = factor;
  a.failure = "scripted: no convergence";
  return a;
}

StepAttempt withIterations(int n) {
  StepAttempt a;
  a.measure.iterations = n;
  return a;
}

// A method whose history cannot serve a doubled step says so through nextStepCap (abm3): the
// step is held instead of doubled, and doubles once the cap allows it.
TEST(HalvingDoublingControl, ADoublingPastTheMethodsCapWaits) {
  System s = harmonic(0.0).build();
  HalvingDoublingParams p;
  p.quantity = HalvingDoublingParams::Quantity::kIterations;
  p.lower = 2;
  p.upper = 10;
  p.initialStep = 0.01;
  Scripted method(std::make_unique<HalvingDoublingControl>(p));
  method.rule = [&](const StepContext& step) {
    StepAttempt a = withIterations(1);
    a.measure.nextStepCap = method.attempts.size() < 3 ? step.h : 2.0 * step.h;
    return a;
  };
  ASSERT_TRUE(method.advance(s, 0.1).ok);
  ASSERT_GE(method.attempts.size(), 4u);
  EXPECT_DOUBLE_EQ(method.attempts[1].h, 0.01);
  EXPECT_DOUBLE_EQ(method.attempts[2].h, 0.01);
  EXPECT_DOUBLE_EQ(method.attempts[3].h, 0.02);
}

TEST(FixedStepControl, EqualStepsFromACountOrALongestLength) {
  EXPECT_EQ(FixedStepControl::ofLength(1e-3).equalSteps(0.01, 1), 10);
  EXPECT_EQ(FixedStepControl::ofLength(1e-3).equalSteps(0.01, 2), 20);
  EXPECT_EQ(FixedStepControl::ofLength(3e-3).equalSteps(0.01, 1), 4);
  EXPECT_EQ(FixedStepControl::ofCount(3).equalSteps(0.01, 4), 3);
  EXPECT_EQ(FixedStepControl::ofCount(0).equalSteps(0.01, 1), 1);
}

TEST(FrameLoop, FixedStepsEndExactlyAtTheFrameEndAndAStepThatFailsRestoresTheFrame) {
  System s = harmonic(0.0).build();
  Scripted method(std::make_unique<FixedStepControl>(FixedStepControl::ofLength(0.03)));
  StepReport r = method.advance(s, 0.1);
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_EQ(r.substeps, 4);
  EXPECT_EQ(s.state.t, 0.1);
  ASSERT_EQ(method.attempts.size(), 4u);
  EXPECT_TRUE(method.attempts.back().lastInFrame);
  EXPECT_DOUBLE_EQ(method.attempts[1].t, 0.025);

  const Eigen::VectorXd before = s.state.x;
  method.script = {StepAttempt{}, notConverged(0.5)};
  r = method.advance(s, 0.1);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.failure, "scripted: no convergence");
  EXPECT_EQ(s.state.x, before) << "the frame's initial state must be back";
  EXPECT_EQ(s.state.t, 0.1);
  EXPECT_EQ(method.abandoned, 1);
}

TEST(FrameLoop, AdaptiveRetriesShorterAfterNoConvergenceAndStopsAtTheAttemptLimit) {
  System s = harmonic(0.0).build();
  HalvingDoublingParams p;
  p.quantity = HalvingDoublingParams::Quantity::kIterations;
  p.lower = 2;
  p.upper = 10;
  p.initialStep = 0.04;
  Scripted method(std::make_unique<HalvingDoublingControl>(p), 50);
  method.script = {notConverged(0.25), withIterations(5), withIterations(2)};
  method.rule = [](const StepContext&) { return withIterations(5); };
  StepReport r = method.advance(s, 0.1);
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_EQ(r.rejected, 1);
  ASSERT_GE(method.attempts.size(), 4u);
  EXPECT_DOUBLE_EQ(method.attempts[1].h, 0.01);  // 0.25 * 0.04
  EXPECT_TRUE(method.attempts[1].afterRejection);
  EXPECT_DOUBLE_EQ(method.attempts[2].h, 0.01);  // 5 iterations: within the limits
  EXPECT_DOUBLE_EQ(method.attempts[3].h, 0.02);  // 2 iterations: at the lower limit
  EXPECT_NEAR(s.state.t, 0.1, 1e-15);
  EXPECT_TRUE(method.attempts.back().lastInFrame);

  // Never converging: the frame ends at the attempt limit or the minimum step, restored.
  method.rule = [](const StepContext&) { return notConverged(0.5); };
  const Eigen::VectorXd before = s.state.x;
  r = method.advance(s, 0.1);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("step size underflow"), std::string::npos) << r.failure;
  EXPECT_EQ(s.state.x, before);

  p.minStep = 1e-300;
  Scripted limited(std::make_unique<HalvingDoublingControl>(p), 50);
  limited.rule = [](const StepContext&) { return notConverged(0.9); };
  r = limited.advance(s, 0.1);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("more than 50 step attempts"), std::string::npos) << r.failure;
}

TEST(HalvingDoublingControl, IterationCountsHalveAboveTheUpperLimitWithoutRedoing) {
  // The iteration-count control of implicit Euler in the Adamss chapter (Sec. 2.5.5).
  System s = harmonic(0.0).build();
  HalvingDoublingParams p;
  p.quantity = HalvingDoublingParams::Quantity::kIterations;
  p.lower = 3;
  p.upper = 20;
  p.rejectAboveUpper = false;
  p.initialStep = 0.02;
  Scripted method(std::make_unique<HalvingDoublingControl>(p));
  method.script = {withIterations(40), withIterations(10)};
  method.rule = [](const StepContext&) { return withIterations(10); };
  const StepReport r = method.advance(s, 0.1);
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_EQ(r.rejected, 0);
  EXPECT_DOUBLE_EQ(method.attempts[0].h, 0.02);
  EXPECT_DOUBLE_EQ(method.attempts[1].h, 0.01);
  EXPECT_DOUBLE_EQ(method.attempts[2].h, 0.01);
}

// keepAtMinStep (backward Euler's iteration control): a step at minStep is kept whatever it
// measured, no halving goes below minStep (3 ms halves to 2, not 1.5), and the frame goes on
// where without it the step would underflow.
TEST(HalvingDoublingControl, KeepAtMinStepKeepsTheShortestStepInsteadOfFailing) {
  System s = harmonic(0.0).build();
  HalvingDoublingParams p;
  p.quantity = HalvingDoublingParams::Quantity::kIterations;
  p.lower = 2;
  p.upper = 10;
  p.initialStep = 0.003;
  p.minStep = 0.002;
  p.keepAtMinStep = true;
  Scripted method(std::make_unique<HalvingDoublingControl>(p));
  method.rule = [](const StepContext&) { return withIterations(50); };
  const StepReport r = method.advance(s, 0.01);
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_EQ(r.rejected, 1);
  EXPECT_EQ(r.substeps, 5);
  ASSERT_GE(method.attempts.size(), 2u);
  EXPECT_DOUBLE_EQ(method.attempts[1].h, 0.002);
  for (size_t k = 1; k < method.attempts.size(); ++k)
    EXPECT_NEAR(method.attempts[k].h, 0.002, 1e-15) << k;
  EXPECT_NEAR(s.state.t, 0.01, 1e-15);

  p.keepAtMinStep = false;
  Scripted failing(std::make_unique<HalvingDoublingControl>(p));
  failing.rule = method.rule;
  const StepReport f = failing.advance(s, 0.01);
  EXPECT_FALSE(f.ok);
  EXPECT_NE(f.failure.find("step size underflow"), std::string::npos) << f.failure;
}

TEST(ErrorStepControl, ProposalsFollowTheErrorWithinTheGrowthAndShrinkLimits) {
  ErrorStepParams p;
  p.estimatorOrder = 3;
  p.safety = 0.9;
  p.maxGrowth = 8.0;
  p.maxShrink = 5.0;
  p.initialStep = 1e-3;
  p.holdBelowGrowth = 1.0;
  ErrorStepControl c(p);
  c.restart();
  EXPECT_DOUBLE_EQ(c.proposedStep(), 1e-3);
  StepMeasure m;
  m.error = 50.0;  // a first step far off: one tenth
  EXPECT_FALSE(c.judge(1e-3, m, false));
  EXPECT_DOUBLE_EQ(c.proposedStep(), 1e-4);
  m.error = 0.5 * 0.5 * 0.5 * 0.5 * std::pow(0.9, 4);  // h_new = h / (0.5 0.9 / 0.9) = 2h,
  EXPECT_TRUE(c.judge(1e-4, m, false));                // held at h after a rejection
  EXPECT_DOUBLE_EQ(c.proposedStep(), 1e-4);
  m.error = 1e-12;
  EXPECT_TRUE(c.judge(1e-4, m, false));
  EXPECT_NEAR(c.proposedStep(), 8e-4, 1e-18) << "growth is limited to maxGrowth";
  m.error = 1e6;
  EXPECT_FALSE(c.judge(8e-4, m, false));
  EXPECT_NEAR(c.proposedStep(), 8e-4 / 5.0, 1e-18) << "shrinking is limited to maxShrink";
  m.error = 1e-12;
  m.nextStepCap = 2e-4;
  EXPECT_TRUE(c.judge(1.6e-4, m, false));
  EXPECT_DOUBLE_EQ(c.proposedStep(), 1.6e-4) << "no growth right after a rejection";
  EXPECT_TRUE(c.judge(1.6e-4, m, false));
  EXPECT_DOUBLE_EQ(c.proposedStep(), 2e-4) << "the method's cap";
  EXPECT_THROW(ErrorStepControl(ErrorStepParams{1e-3, 1e-14, 1e30, 0}), std::invalid_argument);
}

// The rule of "Numerical Recipes", Sec. 16.2: h 0.9 e^-0.2 after a kept step (at most 4 h),
// h 0.9 e^-0.25 after a rejected one (at least h / 10).
TEST(PowerLawStepControl, ProposalsFollowTheGrowAndShrinkExponentsWithinTheirLimits) {
  PowerLawStepParams p;
  p.initialStep = 1e-3;
  PowerLawStepControl c(p);
  c.restart();
  EXPECT_DOUBLE_EQ(c.proposedStep(), 1e-3);
  StepMeasure m;
  m.error = 0.5;
  EXPECT_TRUE(c.judge(1e-3, m, false));
  EXPECT_NEAR(c.proposedStep(), 1e-3 * 0.9 * std::pow(0.5, -0.2), 1e-18);
  m.error = 1.0;  // exactly at the tolerance: kept, the next step 10 % shorter
  EXPECT_TRUE(c.judge(1e-3, m, false));
  EXPECT_NEAR(c.proposedStep(), 0.9e-3, 1e-18);
  m.error = 1e-9;
  EXPECT_TRUE(c.judge(1e-3, m, false));
  EXPECT_NEAR(c.proposedStep(), 4e-3, 1e-18) << "growth is limited to 4x";
  m.error = 0.0;
  EXPECT_TRUE(c.judge(1e-3, m, false));
  EXPECT_NEAR(c.proposedStep(), 4e-3, 1e-18) << "a zero error grows by the limit";
  m.error = 3.0;
  EXPECT_FALSE(c.judge(1e-3, m, false));
  EXPECT_NEAR(c.proposedStep(), 1e-3 * 0.9 * std::pow(3.0, -0.25), 1e-18);
  m.error = 1e9;
  EXPECT_FALSE(c.judge(1e-3, m, false));
  EXPECT_NEAR(c.proposedStep(), 1e-4, 1e-18) << "shrinking is limited to 10x";
  m.error = 1e-9;
  m.nextStepCap = 2e-3;
  EXPECT_TRUE(c.judge(1e-3, m, false));
  EXPECT_NEAR(c.proposedStep(), 2e-3, 1e-18) << "the method's cap";
  PowerLawStepParams bad;
  bad.maxGrowth = 1.0;
  EXPECT_THROW(PowerLawStepControl{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace tt
