#include "tissue_trainer/core/integrate/rk4_adaptive.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>

#include "frame_guard.h"

namespace tt {

namespace {

// Richardson's factor for a fourth-order method halved once: 2^4 - 1.
constexpr double kRichardson = 15.0;

const Rk4AdaptiveParams& checked(const Rk4AdaptiveParams& p) {
  if (!(p.timeStep > 0.0) || !(p.absTol > 0.0) || !(p.absTolVelocity > 0.0) ||
      !(p.relTol >= 0.0) || !(p.minStep > 0.0) || !(p.maxStep >= p.minStep) ||
      p.maxSubsteps < 1)
    throw std::invalid_argument(
        "rk4_adaptive: needs positive steps and absolute tolerances, rel_tol >= 0, min_step <= "
        "max_step and max_substeps >= 1");
  return p;
}

std::unique_ptr<StepSizeController> makeControl(const Rk4AdaptiveParams& p) {
  if (!p.adaptive)
    return std::make_unique<FixedStepControl>(FixedStepControl::ofLength(p.timeStep));
  PowerLawStepParams c;  // safety, exponents and limits: the defaults of Sec. 16.2
  c.initialStep = p.timeStep;
  c.minStep = p.minStep;
  c.maxStep = p.maxStep;
  return std::make_unique<PowerLawStepControl>(c);
}

bool constrained(const System& system, Eigen::Index dof) {
  return static_cast<size_t>(dof) < system.isConstrained.size() && system.isConstrained[dof];
}

std::string tooManySteps(long limit, double frameTime, double h) {
  char text[200];
  std::snprintf(text, sizeof text,
                "rk4_adaptive: more than %ld steps in one frame of %.6g s (last step %.6g s); "
                "raise max_substeps or loosen abs_tol / rel_tol",
                limit, frameTime, h);
  return text;
}

}  // namespace

Rk4AdaptiveIntegrator::Rk4AdaptiveIntegrator(Rk4AdaptiveParams params)
    : SteppedIntegrator(makeControl(checked(params)), params.maxSubsteps + 1),
      params_(params) {}

// Sizes every buffer (a no-op while the size stays) and checks a fixed frame's step count.
FrameStart Rk4AdaptiveIntegrator::beginFrame(System& system, double frameTime) {
  const Eigen::Index n = system.state.x.size();
  for (Eigen::VectorXd* b : {&force_, &a0_, &x1_, &v1_, &xBig_, &vBig_, &xMid_, &vMid_, &aMid_,
                             &stageX_, &stageV_, &stageA_, &sumV_, &sumA_})
    b->resize(n);
  attemptsInFrame_ = 0;
  frameTime_ = frameTime;
  FrameStart start;
  if (!params_.adaptive) {
    const int steps = detail::equalSubsteps(frameTime, params_.timeStep / stepDivisor());
    if (steps > params_.maxSubsteps)
      start.failure = tooManySteps(params_.maxSubsteps, frameTime, frameTime / steps);
  }
  return start;
}

void Rk4AdaptiveIntegrator::acceleration(const System& system, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd& v, Eigen::VectorXd& a) {
  system.computeForce(x, v, force_);
  a = force_.cwiseQuotient(system.mass);
  ++forceEvaluations_;
}

void Rk4AdaptiveIntegrator::rungeKuttaStep(const System& system, double t, double h,
                                           const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                                           const Eigen::VectorXd& a0, Eigen::VectorXd& x,
                                           Eigen::VectorXd& v) {
  const double half = 0.5 * h;
  stageX_ = x0 + half * v0;  // k2 at y + h/2 k1
  stageV_ = v0 + half * a0;
  system.prescribe(t + half, stageX_, stageV_);
  acceleration(system, stageX_, stageV_, stageA_);
  sumV_ = v0 + 2.0 * stageV_;
  sumA_ = a0 + 2.0 * stageA_;
  stageX_ = x0 + half * stageV_;  // k3 at y + h/2 k2
  stageV_ = v0 + half * stageA_;
  system.prescribe(t + half, stageX_, stageV_);
  acceleration(system, stageX_, stageV_, stageA_);
  sumV_ += 2.0 * stageV_;
  sumA_ += 2.0 * stageA_;
  stageX_ = x0 + h * stageV_;  // k4 at y + h k3
  stageV_ = v0 + h * stageA_;
  system.prescribe(t + h, stageX_, stageV_);
  acceleration(system, stageX_, stageV_, stageA_);
  sumV_ += stageV_;
  sumA_ += stageA_;
  x = x0 + (h / 6.0) * sumV_;
  v = v0 + (h / 6.0) * sumA_;
  system.prescribe(t + h, x, v);
}

StepAttempt Rk4AdaptiveIntegrator::attempt(System& system, const StepContext& step,
                                           StepReport&) {
  if (++attemptsInFrame_ > params_.maxSubsteps) {
    StepAttempt out;
    out.status = StepStatus::kFailed;
    out.failure = tooManySteps(params_.maxSubsteps, frameTime_, step.h);
    return out;
  }
  const State& s = system.state;
  acceleration(system, s.x, s.v, a0_);
  if (!params_.adaptive) {
    rungeKuttaStep(system, step.t, step.h, s.x, s.v, a0_, x1_, v1_);
    system.prescribe(step.end, x1_, v1_);  // step.end, not t + h: the frame's exact end
    return finished(step, std::numeric_limits<double>::quiet_NaN());
  }
  const double half = 0.5 * step.h;
  rungeKuttaStep(system, step.t, step.h, s.x, s.v, a0_, xBig_, vBig_);
  rungeKuttaStep(system, step.t, half, s.x, s.v, a0_, xMid_, vMid_);
  acceleration(system, xMid_, vMid_, aMid_);
  rungeKuttaStep(system, step.t + half, half, xMid_, vMid_, aMid_, x1_, v1_);
  const double error = doublingError(system);
  if (params_.extrapolate) {
    x1_ += (x1_ - xBig_) / kRichardson;
    v1_ += (v1_ - vBig_) / kRichardson;
  }
  system.prescribe(step.end, x1_, v1_);
  return finished(step, error);
}

double Rk4AdaptiveIntegrator::doublingError(const System& system) const {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < x1_.size(); ++i) {
    if (constrained(system, i)) continue;
    const double dx = std::abs(x1_[i] - xBig_[i]) / kRichardson;
    const double dv = std::abs(v1_[i] - vBig_[i]) / kRichardson;
    worst = std::max({worst, dx / (params_.absTol + params_.relTol * std::abs(x1_[i])),
                      dv / (params_.absTolVelocity + params_.relTol * std::abs(v1_[i]))});
  }
  return worst;
}

StepAttempt Rk4AdaptiveIntegrator::finished(const StepContext& step, double error) const {
  StepAttempt out;
  if ((params_.adaptive && !std::isfinite(error)) || !x1_.allFinite() || !v1_.allFinite()) {
    char text[128];
    std::snprintf(text, sizeof text,
                  "rk4_adaptive: non-finite state at t = %.6g s (step %.6g s; explicit method)",
                  step.end, step.h);
    out.status = StepStatus::kFailed;
    out.failure = text;
    return out;
  }
  out.measure.error = error;
  return out;
}

std::string Rk4AdaptiveIntegrator::accept(System& system, const StepContext& step) {
  State& s = system.state;
  s.x.swap(x1_);
  s.v.swap(v1_);
  s.t = step.end;
  return "";
}

}  // namespace tt
