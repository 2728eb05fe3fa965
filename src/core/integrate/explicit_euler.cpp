#include "tissue_trainer/core/integrate/explicit_euler.h"

#include "frame_guard.h"

namespace tt {

StepReport ExplicitEulerIntegrator::advance(System& system, double frameTime) {
  StepReport report;
  detail::FrameGuard guard(system.state);
  const int n = detail::equalSubsteps(frameTime, currentStep(params.substep));
  const double h = frameTime / n;
  State& s = system.state;
  for (int i = 0; i < n; ++i) {
    system.computeForce(s.x, s.v, force_);
    if (params.symplectic) {
      s.v += h * force_.cwiseQuotient(system.mass);
      s.x += h * s.v;
    } else {
      s.x += h * s.v;  // old velocity: Eq 2.130
      s.v += h * force_.cwiseQuotient(system.mass);
    }
    s.t = detail::substepEnd(guard.start().t, frameTime, i, n);
    system.prescribe(s.t, s.x, s.v);
    if (!detail::FrameGuard::finite(s)) {
      guard.restore(s, report,
                    std::string(name()) + ": non-finite state at t = " + std::to_string(s.t) +
                        " (step " + std::to_string(h) + " s)");
      break;
    }
    ++report.substeps;
    report.lastStep = h;
  }
  guard.finish(report);
  return report;
}

}  // namespace tt
