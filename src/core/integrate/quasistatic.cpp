#include "tissue_trainer/core/integrate/quasistatic.h"

namespace tt {

QuasistaticIntegrator::QuasistaticIntegrator(EquilibriumParams params)
    : SteppedIntegrator(std::make_unique<FixedStepControl>(FixedStepControl::ofCount(1))),
      solver_(params) {}

FrameStart QuasistaticIntegrator::beginFrame(System& system, double) {
  FrameStart start;
  if (!system.hasStiffness())
    start.failure = "quasistatic: every force model must provide its stiffness";
  return start;
}

StepAttempt QuasistaticIntegrator::attempt(System& system, const StepContext& step,
                                           StepReport& report) {
  // The equilibrium is that of the step's end: boundary positions here, time-dependent loads
  // through stepUpdateTime.
  x_ = system.state.x;
  v_ = system.state.v;
  system.prescribe(step.end, x_, v_);
  last_ = solver_.solve(system, x_);
  report.newtonIterations += last_.newtonIterations;
  report.linearIterations += last_.linearIterations;
  report.jacobians +=
      last_.newtonIterations + last_.pseudoTimeSteps + last_.rejectedPseudoTimeSteps;
  StepAttempt out;
  out.measure.iterations = last_.newtonIterations;
  if (!last_.converged()) {
    out.status = last_.stop == EquilibriumStop::kNonFiniteForce ? StepStatus::kFailed
                                                                : StepStatus::kNotConverged;
    out.failure = "quasistatic: " + last_.reason + " at t = " + std::to_string(step.end);
  }
  return out;
}

std::string QuasistaticIntegrator::accept(System& system, const StepContext& step) {
  State& s = system.state;
  s.x.swap(x_);
  s.v.setZero(s.x.size());
  s.t = step.end;
  return "";
}

}  // namespace tt
