#pragma once
// The third-order Adams-Bashforth-Moulton predictor-corrector of "Adamss: Advanced
// Anisotropic Mass-Spring System", Sec. 2.5.4, on the first-order system y = (x, v),
// y' = (v, a), a = M^-1 f(x, v). With f_j = (v_j, a_j) at the equally spaced t_i, t_i - h,
// t_i - 2h:
//   predictor (Eqs 2.138-2.139)  y~ = y_i + h (23 f_i - 16 f_i-1 + 5 f_i-2) / 12
//   corrector                    y+ = y_i + h (5 f(y~) + 8 f_i - f_i-1) / 12
// and f(y+) is evaluated for the next step (PECE). The corrector as printed in Sec. 2.5.4
// (Eqs 2.140-2.141) puts the predicted velocity where f(y~)'s acceleration belongs and the
// predicted position where its velocity belongs; that scheme does not converge (its error
// does not fall with h), so the corrector here is the Adams-Moulton one the text describes.
// Global order 3 with third-order starting values, 2 with the chapter's forward-Euler start.
//
// Start-up: a step the history cannot serve (fewer than three points, or a step so long that
// t_i - 2h lies before the oldest kept point) is taken by the starting method: the third-order
// Runge-Kutta method of Bogacki and Shampine with its embedded second-order error estimate
// (default), or forward Euler with the estimate h/2 |f(y+) - f(y_i)|.
//
// Adaptive step (HalvingDoublingControl): the predictor-corrector difference, per DOF over
// the tolerance atol + rtol |y+| (positions and velocities each with their own atol). Above 1
// the step is halved and redone; when every DOF is at or below lowerRatio, the next step is
// twice as long, provided the history holds the points t_i - 2h and t_i - 4h (thinning:
// every other point). The history keeps the last points actually reached; a point a step
// needs between them is interpolated, linearly as in the chapter (v and a each) or by cubic
// Hermite interpolation of x (with v) and v (with a), a then from the force at that state.
//
// Constrained DOFs take their prescribed values at every evaluated state. The history
// survives between frames while the state is the one the integrator left; otherwise (and
// after a failed frame) the method starts again.
#include <Eigen/Core>
#include <array>
#include <string>

#include "tissue_trainer/core/integrate/stepped_integrator.h"

namespace tt {

struct Abm3Params {
  enum class Start { kRungeKutta3, kEuler };
  enum class Interpolation { kLinear, kHermite };
  bool adaptive = true;
  double timeStep = 1e-4;  // s; the first step (adaptive) or the longest step (fixed)
  Start start = Start::kRungeKutta3;
  Interpolation interpolation = Interpolation::kLinear;
  double absTol = 1e-6;          // m, positions
  double absTolVelocity = 1e-6;  // m/s
  double relTol = 1e-6;
  double lowerRatio = 0.03;  // doubling threshold as a fraction of the tolerance
  double minStep = 1e-12, maxStep = 1e30;  // s
};

class Abm3Integrator : public SteppedIntegrator {
 public:
  // Throws std::invalid_argument for tolerances or steps that are not positive or a
  // lowerRatio outside (0, 1).
  explicit Abm3Integrator(Abm3Params params = {});
  const char* name() const override { return "abm3"; }
  const Abm3Params& params() const { return params_; }

  // Steps taken by the starting method since construction.
  long startSteps() const { return startSteps_; }

 private:
  static constexpr int kWindow = 6;  // kept points: a doubling needs 5, one spare for a cut step
  struct Point {
    double t = 0.0;
    Eigen::VectorXd x, v, a;
  };

  FrameStart beginFrame(System& system, double frameTime) override;
  StepAttempt attempt(System& system, const StepContext& step, StepReport& report) override;
  std::string accept(System& system, const StepContext& step) override;
  void abandonFrame(const System&) override { count_ = 0; }
  std::string instabilityHint() const override { return "; explicit method"; }

  bool continuesFrom(const State& s) const;
  void resetHistory(const System& system);
  const Point& point(int back) const { return window_[(newest_ + kWindow - back) % kWindow]; }
  bool historyCovers(double t, double h) const;
  // The derivative (v, a) at t, from a kept point or interpolated into scratch slot `slot`.
  const Point& pointAt(const System& system, double t, double h, int slot);
  void interpolate(const System& system, const Point& older, const Point& newer, double t,
                   Point& out);

  StepAttempt abmStep(System& system, const StepContext& step);
  StepAttempt rungeKutta3Step(System& system, const StepContext& step);
  StepAttempt eulerStep(System& system, const StepContext& step);
  StepAttempt measured(const StepContext& step, double error) const;
  void acceleration(const System& system, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                    Eigen::VectorXd& a);
  double weighted(double difference, double value, double absTol) const;
  double nextStepCap(double tEnd) const;

  Abm3Params params_;
  std::array<Point, kWindow> window_;
  int newest_ = 0, count_ = 0;
  std::array<Point, 2> scratch_;  // interpolated points t_i - h, t_i - 2h
  Eigen::VectorXd force_, x1_, v1_, a1_;  // the attempted step's end (a1_ when known)
  bool endAccelerationKnown_ = false;
  bool startedLast_ = false;  // the last attempt was the starting method's
  Eigen::VectorXd stageX_, stageV_, stageA_, stage2V_, stage2A_;  // predictor / RK stages
  long startSteps_ = 0;
};

}  // namespace tt
