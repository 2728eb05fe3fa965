#pragma once
// The explicit Euler method of the Adamss thesis chapter (Sec. 2.5.2, Eqs 2.129-2.130):
//   v+ = v + h M^-1 f(x, v),   x+ = x + h v
// Both updates use the old values, so this is the classical forward Euler method (not the
// symplectic one): on an undamped oscillator it multiplies the energy by exactly
// 1 + (h omega)^2 every step and is unstable for every h > 0 (the growth of the chapter's
// Fig 2.20). The option symplectic uses x+ = x + h v+ instead (semi-implicit or symplectic
// Euler), which is stable for h < 2 / omega_max without damping.
#include <Eigen/Core>

#include "tissue_trainer/core/integrate/stepped_integrator.h"

namespace tt {

struct ExplicitEulerParams {
  double substep = 1e-4;   // s; a frame is split into equal substeps no longer than this
  bool symplectic = false; // position update with the new velocity
};

class ExplicitEulerIntegrator : public SteppedIntegrator {
 public:
  explicit ExplicitEulerIntegrator(ExplicitEulerParams params = {});
  const char* name() const override {
    return params_.symplectic ? "symplectic_euler" : "explicit_euler";
  }
  const ExplicitEulerParams& params() const { return params_; }

 private:
  FrameStart beginFrame(System&, double) override { return {}; }
  StepAttempt attempt(System& system, const StepContext& step, StepReport& report) override;
  std::string accept(System& system, const StepContext& step) override;

  ExplicitEulerParams params_;
  Eigen::VectorXd force_, x1_, v1_;
};

}  // namespace tt
