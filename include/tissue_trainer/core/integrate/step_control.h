#pragma once
// Step-size controllers of the shared frame loop (stepped_integrator.h). A controller says how
// long the next step is and whether a step that converged is kept, from what the method
// measured on it (its local error, its iteration count). Four kinds:
//   FixedStepControl        equal steps per frame (a set count, or a set longest length);
//   ErrorStepControl        the error-per-step controller of Hairer and Wanner, "Solving
//                           Ordinary Differential Equations II", Sec. IV.8, with Gustafsson's
//                           predictive correction (as in RADAU5);
//   HalvingDoublingControl  halves the step above an upper limit and doubles it at or below a
//                           lower limit of the error or of the iteration count (the Adamss
//                           thesis chapter, Secs. 2.5.4 and 2.5.5);
//   PowerLawStepControl     the step-doubling rule of Press et al., "Numerical Recipes",
//                           Sec. 16.2: grow with error^(-1/5), shrink with error^(-1/4).
#include <limits>
#include <string>

namespace tt {

// What a converged step measured.
struct StepMeasure {
  // Local error in the method's norm; for ErrorStepControl the weighted norm (1 = exactly at
  // the tolerance). NaN: the method does not estimate it.
  double error = std::numeric_limits<double>::quiet_NaN();
  int iterations = 0;  // Newton or linear-solver iterations of the step
  // The method's own bound on the next step (Radau IIA with the simplified Jacobian).
  double nextStepCap = std::numeric_limits<double>::infinity();
  // The method can take the same step again with the matrices it has (a kept factorization).
  bool sameStepIsCheap = false;
};

class StepSizeController {
 public:
  virtual ~StepSizeController() = default;
  virtual const char* name() const = 0;
  // False: the frame loop cuts each frame into equalSteps() steps and keeps every step that
  // converges; a step that does not converge fails the frame.
  virtual bool adaptive() const = 0;
  // Fixed controllers: steps in a frame; `divisor` shortens a set step length (StabilityGuard).
  virtual int equalSteps(double /*frameTime*/, int /*divisor*/) const { return 1; }
  virtual double minStep() const { return 0.0; }
  virtual double maxStep() const { return std::numeric_limits<double>::infinity(); }

  // Adaptive controllers: the step to try next (unclamped; the loop applies min/max).
  double proposedStep() const { return proposed_; }
  // restart() has been called at least once (the frame loop does it on the first frame).
  bool started() const { return started_; }
  // No step was kept since the last restart / the last attempt was rejected.
  bool fresh() const { return fresh_; }
  bool rejectedLast() const { return rejectedLast_; }

  // Forgets the history: the state was changed from outside, or a frame failed.
  void restart();
  // A converged step of length h: true to keep it. Sets the next proposal either way.
  bool judge(double h, const StepMeasure& measure, bool lastInFrame);
  // A step of length h did not converge; its method suggests factor * h.
  void notConverged(double h, double factor);
  // The frame's last step was cut short of the planned one: the next frame may start there.
  void keepAtLeast(double planned);

 protected:
  virtual double initialStep() const = 0;
  virtual bool keeps(double h, const StepMeasure& measure) const = 0;
  // Next step after a kept (afterKeep) or rejected (afterReject) step of length h; fresh() and
  // rejectedLast() still describe the state before this step.
  virtual double afterKeep(double h, const StepMeasure& measure, bool lastInFrame) = 0;
  virtual double afterReject(double h, const StepMeasure& measure) = 0;

 private:
  double proposed_ = 0.0;
  bool fresh_ = true, rejectedLast_ = false, started_ = false;
};

// Equal steps: `count` per frame, or as few as keep each step at or below `length`.
class FixedStepControl : public StepSizeController {
 public:
  static FixedStepControl ofCount(int count);
  static FixedStepControl ofLength(double length);
  const char* name() const override { return "fixed"; }
  bool adaptive() const override { return false; }
  int equalSteps(double frameTime, int divisor) const override;

 protected:
  double initialStep() const override { return length_; }
  bool keeps(double, const StepMeasure&) const override { return true; }
  double afterKeep(double h, const StepMeasure&, bool) override { return h; }
  double afterReject(double h, const StepMeasure&) override { return h; }

 private:
  int count_ = 1;
  double length_ = 0.0;  // > 0: steps no longer than this (the count follows)
};

struct ErrorStepParams {
  double initialStep = 1e-3;  // s, after a restart
  double minStep = 1e-14;     // s; a shorter proposal fails the frame
  double maxStep = 1e30;      // s
  int estimatorOrder = 3;     // q of the error estimate: the step scales with error^(-1/(q+1))
  double safety = 0.9;
  double maxGrowth = 8.0;     // h_new <= maxGrowth * h
  double maxShrink = 5.0;     // h_new >= h / maxShrink
  // > 0: the safety factor falls as a Newton iteration needs more of its iterations, from
  // safety at none to safety (2 k + 1) / (3 k) at k = newtonIterationLimit (Hairer and Wanner).
  int newtonIterationLimit = 0;
  // Keep h when the proposal grows it by less than this factor and the same step is cheap (a
  // kept factorization); 1 or less: never.
  double holdBelowGrowth = 1.2;
};

class ErrorStepControl : public StepSizeController {
 public:
  // Throws std::invalid_argument for parameters outside the ranges above.
  explicit ErrorStepControl(ErrorStepParams params = {});
  const char* name() const override { return "error"; }
  bool adaptive() const override { return true; }
  double minStep() const override { return params_.minStep; }
  double maxStep() const override { return params_.maxStep; }
  const ErrorStepParams& params() const { return params_; }

 protected:
  double initialStep() const override { return params_.initialStep; }
  bool keeps(double, const StepMeasure& m) const override { return !(m.error >= 1.0); }
  double afterKeep(double h, const StepMeasure& m, bool lastInFrame) override;
  double afterReject(double h, const StepMeasure& m) override;

 private:
  double quotient(const StepMeasure& m) const;  // h / h_new from this step's error alone
  ErrorStepParams params_;
  double exponent_;
  double keptStep_ = 0.0, keptError_ = 1.0;  // the last kept step (predictive correction)
};

struct HalvingDoublingParams {
  enum class Quantity { kError, kIterations };
  Quantity quantity = Quantity::kError;
  double lower = 0.0;  // at or below: the next step is twice as long (unless past nextStepCap)
  double upper = 1.0;  // above: the step is halved (and redone if rejectAboveUpper)
  bool rejectAboveUpper = true;
  double initialStep = 1e-3, minStep = 1e-12, maxStep = 1e30;  // s
  // True: a step at minStep is kept whatever it measured and no proposal falls below minStep
  // (a method whose measure says "costly", not "wrong"); false: a halving below minStep fails
  // the frame.
  bool keepAtMinStep = false;
};

class HalvingDoublingControl : public StepSizeController {
 public:
  // Throws std::invalid_argument unless lower < upper and the step lengths are positive.
  explicit HalvingDoublingControl(HalvingDoublingParams params);
  const char* name() const override { return "halving_doubling"; }
  bool adaptive() const override { return true; }
  double minStep() const override { return params_.minStep; }
  double maxStep() const override { return params_.maxStep; }

 protected:
  double initialStep() const override { return params_.initialStep; }
  bool keeps(double h, const StepMeasure& m) const override;
  double afterKeep(double h, const StepMeasure& m, bool lastInFrame) override;
  double afterReject(double h, const StepMeasure&) override { return halved(h); }

 private:
  double measured(const StepMeasure& m) const;
  double halved(double h) const;
  HalvingDoublingParams params_;
};

// The rule of "Numerical Recipes", Sec. 16.2, for a fourth-order method whose error is
// measured by step doubling: with the error e in the weighted norm (1 = at the tolerance), a
// step with e <= 1 is kept and the next is h safety e^-growExponent, at most maxGrowth h; a
// step with e > 1 is redone with h safety e^-shrinkExponent, at least h / maxShrink. The two
// exponents differ because a kept step's error scales as h^5 (the local error of a fourth-order
// step) while a rejected one is shrunk more cautiously, as if it scaled as h^4.
struct PowerLawStepParams {
  double initialStep = 1e-4;  // s, after a restart
  double minStep = 1e-12;     // s; a shorter proposal fails the frame
  double maxStep = 1e30;      // s
  double safety = 0.9;
  double growExponent = 0.2;
  double shrinkExponent = 0.25;
  double maxGrowth = 4.0;
  double maxShrink = 10.0;
};

class PowerLawStepControl : public StepSizeController {
 public:
  // Throws std::invalid_argument for parameters outside 0 < safety <= 1, positive exponents,
  // growth and shrink limits > 1 and positive steps with minStep <= maxStep.
  explicit PowerLawStepControl(PowerLawStepParams params = {});
  const char* name() const override { return "power_law"; }
  bool adaptive() const override { return true; }
  double minStep() const override { return params_.minStep; }
  double maxStep() const override { return params_.maxStep; }
  const PowerLawStepParams& params() const { return params_; }

 protected:
  double initialStep() const override { return params_.initialStep; }
  bool keeps(double, const StepMeasure& m) const override { return m.error <= 1.0; }
  double afterKeep(double h, const StepMeasure& m, bool lastInFrame) override;
  double afterReject(double h, const StepMeasure& m) override;

 private:
  PowerLawStepParams params_;
};

}  // namespace tt
