#include "tissue_trainer/core/integrate/explicit_euler.h"

namespace tt {

ExplicitEulerIntegrator::ExplicitEulerIntegrator(ExplicitEulerParams params)
    : SteppedIntegrator(
          std::make_unique<FixedStepControl>(FixedStepControl::ofLength(params.substep))),
      params_(params) {}

StepAttempt ExplicitEulerIntegrator::attempt(System& system, const StepContext& step,
                                             StepReport&) {
  const State& s = system.state;
  const double h = step.h;
  system.computeForce(s.x, s.v, force_);
  v1_ = s.v + h * force_.cwiseQuotient(system.mass);
  x1_ = s.x + h * (params_.symplectic ? v1_ : s.v);  // old velocity: Eq 2.130
  return {};
}

std::string ExplicitEulerIntegrator::accept(System& system, const StepContext& step) {
  State& s = system.state;
  s.x.swap(x1_);
  s.v.swap(v1_);
  s.t = step.end;
  system.prescribe(s.t, s.x, s.v);
  return "";
}

}  // namespace tt
