#include "tissue_trainer/core/integrate/abm3.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

namespace tt {

namespace {

// Two times closer than this fraction of the step are the same point.
constexpr double kSameTime = 1e-9;

const Abm3Params& checked(const Abm3Params& p) {
  if (!(p.timeStep > 0.0) || !(p.absTol > 0.0) || !(p.absTolVelocity > 0.0) ||
      !(p.relTol >= 0.0) || !(p.lowerRatio > 0.0 && p.lowerRatio < 1.0) ||
      !(p.minStep > 0.0) || !(p.maxStep >= p.minStep))
    throw std::invalid_argument(
        "abm3: needs positive steps and absolute tolerances, rel_tol >= 0, min_step <= "
        "max_step and 0 < lower_ratio < 1");
  return p;
}

std::unique_ptr<StepSizeController> makeControl(const Abm3Params& p) {
  if (!p.adaptive)
    return std::make_unique<FixedStepControl>(FixedStepControl::ofLength(p.timeStep));
  HalvingDoublingParams c;
  c.quantity = HalvingDoublingParams::Quantity::kError;
  c.lower = p.lowerRatio;
  c.upper = 1.0;  // the measure is the difference over the tolerance
  c.rejectAboveUpper = true;
  c.initialStep = p.timeStep;
  c.minStep = p.minStep;
  c.maxStep = p.maxStep;
  return std::make_unique<HalvingDoublingControl>(c);
}

std::string nonFinite(const StepContext& step) {
  char text[96];
  std::snprintf(text, sizeof text, "abm3: non-finite state at t = %.6g s (step %.6g s)",
                step.end, step.h);
  return text;
}

bool constrained(const System& system, Eigen::Index dof) {
  return static_cast<size_t>(dof) < system.isConstrained.size() && system.isConstrained[dof];
}

}  // namespace

Abm3Integrator::Abm3Integrator(Abm3Params params)
    : SteppedIntegrator(makeControl(checked(params))), params_(params) {}

bool Abm3Integrator::continuesFrom(const State& s) const {
  if (count_ == 0) return false;
  const Point& p = point(0);
  return s.t == p.t && s.x.size() == p.x.size() && s.x == p.x && s.v == p.v;
}

FrameStart Abm3Integrator::beginFrame(System& system, double) {
  if (continuesFrom(system.state)) return {};
  resetHistory(system);
  FrameStart start;
  start.continues = false;
  return start;
}

// Sizes every buffer once (a no-op while the size stays) and keeps the state as the only point.
void Abm3Integrator::resetHistory(const System& system) {
  const State& s = system.state;
  const Eigen::Index n = s.x.size();
  for (Point& p : window_) {
    p.x.resize(n);
    p.v.resize(n);
    p.a.resize(n);
  }
  for (Point& p : scratch_) {
    p.x.resize(n);
    p.v.resize(n);
    p.a.resize(n);
  }
  for (Eigen::VectorXd* b : {&force_, &x1_, &v1_, &a1_, &stageX_, &stageV_, &stageA_, &stage2V_,
                             &stage2A_})
    b->resize(n);
  newest_ = 0;
  count_ = 1;
  Point& p = window_[0];
  p.t = s.t;
  p.x = s.x;
  p.v = s.v;
  acceleration(system, p.x, p.v, p.a);
}

void Abm3Integrator::acceleration(const System& system, const Eigen::VectorXd& x,
                                  const Eigen::VectorXd& v, Eigen::VectorXd& a) {
  system.computeForce(x, v, force_);
  a = force_.cwiseQuotient(system.mass);
}

double Abm3Integrator::weighted(double difference, double value, double absTol) const {
  return std::abs(difference) / (absTol + params_.relTol * std::abs(value));
}

bool Abm3Integrator::historyCovers(double t, double h) const {
  return count_ >= 3 && point(count_ - 1).t <= t - 2.0 * h + kSameTime * h;
}

StepAttempt Abm3Integrator::attempt(System& system, const StepContext& step, StepReport&) {
  endAccelerationKnown_ = false;
  startedLast_ = !historyCovers(step.t, step.h);
  if (!startedLast_) return abmStep(system, step);
  return params_.start == Abm3Params::Start::kEuler ? eulerStep(system, step)
                                                    : rungeKutta3Step(system, step);
}

const Abm3Integrator::Point& Abm3Integrator::pointAt(const System& system, double t, double h,
                                                     int slot) {
  for (int back = 0; back < count_; ++back) {
    const Point& p = point(back);
    if (std::abs(p.t - t) <= kSameTime * h) return p;
    if (p.t < t) {  // between this point and the next newer one (back > 0: point(0).t > t)
      interpolate(system, p, point(back - 1), t, scratch_[slot]);
      return scratch_[slot];
    }
  }
  return point(count_ - 1);  // not reached: historyCovers checked the span
}

void Abm3Integrator::interpolate(const System& system, const Point& older, const Point& newer,
                                 double t, Point& out) {
  const double span = newer.t - older.t, s = (t - older.t) / span;
  out.t = t;
  if (params_.interpolation == Abm3Params::Interpolation::kLinear) {
    out.v = (1.0 - s) * older.v + s * newer.v;
    out.a = (1.0 - s) * older.a + s * newer.a;
    return;
  }
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = (s3 - 2 * s2 + s) * span;
  const double h01 = -2 * s3 + 3 * s2, h11 = (s3 - s2) * span;
  out.x = h00 * older.x + h10 * older.v + h01 * newer.x + h11 * newer.v;
  out.v = h00 * older.v + h10 * older.a + h01 * newer.v + h11 * newer.a;
  system.prescribe(t, out.x, out.v);
  acceleration(system, out.x, out.v, out.a);
}

// Predictor (Eqs 2.138-2.139), the corrected Adams-Moulton corrector, and their difference.
StepAttempt Abm3Integrator::abmStep(System& system, const StepContext& step) {
  const double h = step.h, w = h / 12.0;
  const Point& p0 = point(0);
  const Point& p1 = pointAt(system, step.t - h, h, 0);
  const Point& p2 = pointAt(system, step.t - 2.0 * h, h, 1);
  stageX_ = p0.x + w * (23.0 * p0.v - 16.0 * p1.v + 5.0 * p2.v);
  stageV_ = p0.v + w * (23.0 * p0.a - 16.0 * p1.a + 5.0 * p2.a);
  system.prescribe(step.end, stageX_, stageV_);
  acceleration(system, stageX_, stageV_, stageA_);
  x1_ = p0.x + w * (5.0 * stageV_ + 8.0 * p0.v - p1.v);
  v1_ = p0.v + w * (5.0 * stageA_ + 8.0 * p0.a - p1.a);
  system.prescribe(step.end, x1_, v1_);
  double worst = 0.0;
  for (Eigen::Index i = 0; i < x1_.size(); ++i)
    worst = std::max({worst, weighted(x1_[i] - stageX_[i], x1_[i], params_.absTol),
                      weighted(v1_[i] - stageV_[i], v1_[i], params_.absTolVelocity)});
  return measured(step, worst);
}

// Bogacki-Shampine 3(2): k1 = f(y0), k2 = f(y0 + h/2 k1), k3 = f(y0 + 3h/4 k2),
// y1 = y0 + h (2 k1 + 3 k2 + 4 k3) / 9, and the embedded difference
// h (-5/72 k1 + 1/12 k2 + 1/9 k3 - 1/8 f(y1)).
StepAttempt Abm3Integrator::rungeKutta3Step(System& system, const StepContext& step) {
  const double h = step.h;
  const Point& p0 = point(0);
  stageX_ = p0.x + 0.5 * h * p0.v;
  stage2V_ = p0.v + 0.5 * h * p0.a;
  system.prescribe(step.t + 0.5 * h, stageX_, stage2V_);
  acceleration(system, stageX_, stage2V_, stage2A_);
  stageX_ = p0.x + 0.75 * h * stage2V_;
  stageV_ = p0.v + 0.75 * h * stage2A_;
  system.prescribe(step.t + 0.75 * h, stageX_, stageV_);
  acceleration(system, stageX_, stageV_, stageA_);
  x1_ = p0.x + h / 9.0 * (2.0 * p0.v + 3.0 * stage2V_ + 4.0 * stageV_);
  v1_ = p0.v + h / 9.0 * (2.0 * p0.a + 3.0 * stage2A_ + 4.0 * stageA_);
  system.prescribe(step.end, x1_, v1_);
  acceleration(system, x1_, v1_, a1_);
  endAccelerationKnown_ = true;
  double worst = 0.0;
  for (Eigen::Index i = 0; i < x1_.size(); ++i) {
    if (constrained(system, i)) continue;
    const double dx = h * (-5.0 / 72 * p0.v[i] + stage2V_[i] / 12 + stageV_[i] / 9 - v1_[i] / 8);
    const double dv = h * (-5.0 / 72 * p0.a[i] + stage2A_[i] / 12 + stageA_[i] / 9 - a1_[i] / 8);
    worst = std::max({worst, weighted(dx, x1_[i], params_.absTol),
                      weighted(dv, v1_[i], params_.absTolVelocity)});
  }
  return measured(step, worst);
}

// Forward Euler with the local error estimate h/2 (f(y1) - f(y0)).
StepAttempt Abm3Integrator::eulerStep(System& system, const StepContext& step) {
  const double h = step.h;
  const Point& p0 = point(0);
  x1_ = p0.x + h * p0.v;
  v1_ = p0.v + h * p0.a;
  system.prescribe(step.end, x1_, v1_);
  acceleration(system, x1_, v1_, a1_);
  endAccelerationKnown_ = true;
  double worst = 0.0;
  for (Eigen::Index i = 0; i < x1_.size(); ++i) {
    if (constrained(system, i)) continue;
    worst = std::max({worst, weighted(0.5 * h * (v1_[i] - p0.v[i]), x1_[i], params_.absTol),
                      weighted(0.5 * h * (a1_[i] - p0.a[i]), v1_[i], params_.absTolVelocity)});
  }
  return measured(step, worst);
}

StepAttempt Abm3Integrator::measured(const StepContext& step, double error) const {
  StepAttempt out;
  if (!std::isfinite(error) || !x1_.allFinite() || !v1_.allFinite() ||
      (endAccelerationKnown_ && !a1_.allFinite())) {
    out.status = StepStatus::kFailed;
    out.failure = nonFinite(step);
    return out;
  }
  out.measure.error = error;
  out.measure.nextStepCap = nextStepCap(step.end);
  return out;
}

// Half the span of the newest kWindow - 1 points once this step is kept: a doubled step
// then finds t - 2h and t - 4h among them, and the spare point covers a frame's cut step.
double Abm3Integrator::nextStepCap(double tEnd) const {
  const int kept = std::min(count_ + 1, kWindow - 1);
  return 0.5 * (tEnd - point(kept - 2).t);
}

std::string Abm3Integrator::accept(System& system, const StepContext& step) {
  newest_ = (newest_ + 1) % kWindow;
  count_ = std::min(count_ + 1, kWindow);
  Point& p = window_[newest_];
  p.t = step.end;
  p.x.swap(x1_);
  p.v.swap(v1_);
  if (endAccelerationKnown_) {
    p.a.swap(a1_);
  } else {
    acceleration(system, p.x, p.v, p.a);
  }
  if (startedLast_) ++startSteps_;
  State& s = system.state;
  s.x = p.x;
  s.v = p.v;
  s.t = step.end;
  return "";
}

}  // namespace tt
