#pragma once
// The classical fourth-order Runge-Kutta method with an adaptive step by step doubling, which
// "A non-linear anisotropic Finite Element Method for surgical simulation" (Appendix A) tested
// as an alternative to explicit Euler for its Newtonian scheme (Eq 10), citing Press et al.,
// "Numerical Recipes", Sec. 16.2. It integrates the same first-order system as the other
// explicit methods: y = (x, v), y' = (v, a) with a = M^-1 f(x, v), f every model's force, the
// damping -c v and the external force; constrained DOFs take their prescribed values at every
// evaluated state.
//
// A step of length h: k1 = y'(t, y), k2 = y'(t + h/2, y + h/2 k1), k3 = y'(t + h/2, y + h/2 k2),
// k4 = y'(t + h, y + h k3), y+ = y + h/6 (k1 + 2 k2 + 2 k3 + k4): 4 force evaluations.
//
// Adaptive (the default): each step is taken once as one step of h (y_big) and once as two
// steps of h/2 (y_two), 11 force evaluations (the first stage is shared). Both have a local
// error C h^5 to leading order, y_two's 16 times smaller, so (y_two - y_big) / 15 estimates
// y_two's error. Per DOF it is divided by atol + rtol |y_two| (positions and velocities each
// with their own atol); the largest quotient is the step's error e, and the power-law rule of
// Sec. 16.2 (PowerLawStepControl: safety 0.9, e^-1/5 to grow, at most 4x, e^-1/4 to shrink)
// keeps or redoes it. With local extrapolation (default) the kept state is
// y_two + (y_two - y_big) / 15, fifth order; e still measures y_two's error (a bound, not an
// estimate, of the extrapolated one).
//
// A frame that needs more than maxSubsteps steps (kept and rejected, or equal fixed steps)
// fails with a message naming max_substeps, as does a step proposal below minStep (the frame
// loop's "step size underflow"); the state is then the frame's initial one.
#include <Eigen/Core>
#include <string>

#include "tissue_trainer/core/integrate/stepped_integrator.h"

namespace tt {

struct Rk4AdaptiveParams {
  bool adaptive = true;
  double timeStep = 1e-4;        // s; the first step (adaptive) or the longest step (fixed)
  double absTol = 1e-6;          // m, positions
  double absTolVelocity = 1e-6;  // m/s
  double relTol = 1e-6;
  bool extrapolate = true;       // keep y_two + (y_two - y_big) / 15
  double minStep = 1e-12, maxStep = 1e30;  // s
  long maxSubsteps = 100000;     // steps per frame, kept and rejected
};

class Rk4AdaptiveIntegrator : public SteppedIntegrator {
 public:
  // Throws std::invalid_argument for steps or absolute tolerances that are not positive, a
  // negative relative tolerance, maxStep < minStep or maxSubsteps < 1.
  explicit Rk4AdaptiveIntegrator(Rk4AdaptiveParams params = {});
  const char* name() const override { return "rk4_adaptive"; }
  const Rk4AdaptiveParams& params() const { return params_; }

  // Force evaluations (System::computeForce calls) since construction.
  long forceEvaluations() const { return forceEvaluations_; }

 private:
  FrameStart beginFrame(System& system, double frameTime) override;
  StepAttempt attempt(System& system, const StepContext& step, StepReport& report) override;
  std::string accept(System& system, const StepContext& step) override;
  std::string instabilityHint() const override { return "; explicit method"; }

  // One Runge-Kutta step of length h from (x0, v0) at t with a0 = a(x0, v0) into (x, v),
  // which must not be x0 or v0.
  void rungeKuttaStep(const System& system, double t, double h, const Eigen::VectorXd& x0,
                      const Eigen::VectorXd& v0, const Eigen::VectorXd& a0, Eigen::VectorXd& x,
                      Eigen::VectorXd& v);
  void acceleration(const System& system, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                    Eigen::VectorXd& a);
  // The largest weighted difference (y_two - y_big) / 15 over the free DOFs.
  double doublingError(const System& system) const;
  StepAttempt finished(const StepContext& step, double error) const;

  Rk4AdaptiveParams params_;
  long attemptsInFrame_ = 0, forceEvaluations_ = 0;
  double frameTime_ = 0.0;
  Eigen::VectorXd force_, a0_, x1_, v1_;          // the step's start derivative and its end
  Eigen::VectorXd xBig_, vBig_, xMid_, vMid_, aMid_;  // one step of h; the half-way state
  Eigen::VectorXd stageX_, stageV_, stageA_, sumV_, sumA_;
};

}  // namespace tt
