#pragma once
// The one frame loop of the integrators. A method is a SteppedIntegrator: it says how to start
// a frame, how to attempt one step and how to make an attempted step the state; the loop
// (frame_loop.cpp) walks the frame with a step-size controller (step_control.h), counts what
// was done, keeps the frame's initial state and puts it back when a step fails or leaves a
// non-finite state.
//
// Per frame: beginFrame; then, until the frame's end, attempt a step of the controller's
// length (a fixed controller: equal steps; an adaptive one: its proposal, the last step cut to
// end exactly at the frame's end). A step that converged is judged by the controller: kept
// (accept, the state moves to the step's end) or rejected (retried shorter; the state never
// moved). A step that did not converge is retried with the length the method suggests
// (adaptive) or fails the frame (fixed). endFrame at the end; abandonFrame after a failure.
#include <memory>
#include <string>

#include "tissue_trainer/core/integrate/integrator.h"
#include "tissue_trainer/core/integrate/step_control.h"

namespace tt {

struct StepContext {
  double t = 0.0;         // start of the step
  double h = 0.0;         // its length
  double end = 0.0;       // t + h; exactly the frame's end on its last step
  bool fresh = false;     // no step kept since the method's history was lost
  bool afterRejection = false;  // the previous attempt was rejected or did not converge
  bool lastInFrame = false;
};

enum class StepStatus { kConverged, kNotConverged, kFailed };

struct StepAttempt {
  StepStatus status = StepStatus::kConverged;
  StepMeasure measure;       // kConverged
  double retryFactor = 0.5;  // kNotConverged: try factor * h next
  std::string failure;       // kNotConverged and kFailed: why
};

struct FrameStart {
  bool continues = true;  // false: the method's history was lost (the controller restarts)
  std::string failure;    // not empty: the frame cannot be done
};

class SteppedIntegrator : public Integrator {
 public:
  StepReport advance(System& system, double frameTime) final;
  const StepSizeController& stepControl() const { return *control_; }

 protected:
  explicit SteppedIntegrator(std::unique_ptr<StepSizeController> control,
                             long maxAttemptsPerFrame = 100000)
      : control_(std::move(control)), maxAttempts_(maxAttemptsPerFrame) {}

  virtual FrameStart beginFrame(System& system, double frameTime) = 0;
  // One step from the state at step.t, without changing system.state.
  virtual StepAttempt attempt(System& system, const StepContext& step, StepReport& report) = 0;
  // Makes the last attempt the state at step.end. Returns why not ("" when done).
  virtual std::string accept(System& system, const StepContext& step) = 0;
  virtual void endFrame(System& /*system*/) {}
  // The frame failed and its initial state is back in system.state.
  virtual void abandonFrame(const System& /*system*/) {}
  // Added to the message for a non-finite state ("; explicit limit ..."), or "".
  virtual std::string instabilityHint() const { return ""; }
  // The time at which the models that need it are updated before a step
  // (ForceModel::beginStep): the step's start, or its end for methods that solve for the
  // state at the end alone (the quasistatic solve).
  virtual double stepUpdateTime(const StepContext& step) const { return step.t; }

 private:
  std::unique_ptr<StepSizeController> control_;
  long maxAttempts_;
};

}  // namespace tt
