// The frame loop shared by every SteppedIntegrator (stepped_integrator.h).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "frame_guard.h"
#include "tissue_trainer/core/integrate/stepped_integrator.h"

namespace tt {

namespace {

std::string seconds(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

}  // namespace

StepReport SteppedIntegrator::advance(System& system, double frameTime) {
  StepReport report;
  detail::FrameGuard guard(system.state);
  if (!(frameTime > 0.0)) {
    guard.finish(report);
    return report;
  }
  StepSizeController& control = *control_;
  const auto fail = [&](const std::string& why) {
    guard.restore(system.state, report, why);
    control.restart();
    abandonFrame(system);
    guard.finish(report);
    return report;
  };
  const FrameStart start = beginFrame(system, frameTime);
  if (!start.failure.empty()) return fail(start.failure);
  if (!start.continues || !control.started()) control.restart();

  const double tStart = guard.start().t, tEnd = tStart + frameTime;
  const bool adaptive = control.adaptive();
  const int equalSteps = adaptive ? 0 : control.equalSteps(frameTime, stepDivisor());
  double t = tStart;
  long attempts = 0;
  int kept = 0;
  while (adaptive ? t < tEnd : kept < equalSteps) {
    if (++attempts > maxAttempts_)
      return fail(std::string(name()) + ": more than " + std::to_string(maxAttempts_) +
                  " step attempts in one frame");
    StepContext step;
    step.t = t;
    step.fresh = control.fresh();
    step.afterRejection = control.rejectedLast();
    double planned = 0.0;
    if (adaptive) {
      step.h = control.proposedStep();
      if (!(step.h >= control.minStep()))
        return fail(std::string(name()) + ": step size underflow (" + seconds(step.h) +
                    " s at t = " + seconds(t) + " s)");
      step.h = std::min(step.h, control.maxStep());
      planned = step.h;
      step.lastInFrame = t + 1.0001 * step.h >= tEnd;
      if (step.lastInFrame) step.h = tEnd - t;
      step.end = step.lastInFrame ? tEnd : t + step.h;
    } else {
      step.h = frameTime / equalSteps;
      step.lastInFrame = kept + 1 == equalSteps;
      step.end = detail::substepEnd(tStart, frameTime, kept, equalSteps);
    }

    system.beginStep(stepUpdateTime(step));
    const StepAttempt result = attempt(system, step, report);
    if (result.status == StepStatus::kFailed) return fail(result.failure);
    if (result.status == StepStatus::kNotConverged) {
      if (!adaptive) return fail(result.failure);
      ++report.rejected;
      control.notConverged(step.h, result.retryFactor);
      continue;
    }
    if (!control.judge(step.h, result.measure, step.lastInFrame)) {
      ++report.rejected;
      continue;
    }
    const std::string refused = accept(system, step);
    if (!refused.empty()) return fail(refused);
    if (!detail::FrameGuard::finite(system.state))
      return fail(std::string(name()) + ": non-finite state at t = " + seconds(step.end) +
                  " s (step " + seconds(step.h) + " s" + instabilityHint() + ")");
    if (adaptive && step.lastInFrame && step.h < planned) control.keepAtLeast(planned);
    ++kept;
    ++report.substeps;
    report.lastStep = step.h;
    const double error = result.measure.error;
    if (std::isfinite(error) && !(report.errorEstimate >= error)) report.errorEstimate = error;
    t = step.end;
  }
  endFrame(system);
  guard.finish(report);
  return report;
}

}  // namespace tt
