#pragma once
// Quasistatic "integrator": each frame moves the constrained DOFs to their prescribed positions
// at the frame's end and solves for the equilibrium of the free DOFs there (equilibrium.h),
// warm-started from the last state; velocities are zero. Inertia and damping play no part, so
// the frame time only sets when the boundary paths and time-dependent loads are read. A frame
// whose equilibrium does not converge fails with the solver's reason and the frame's initial
// state back (under the stability guard it is then redone in pieces: smaller load steps).
#include <Eigen/Core>

#include "tissue_trainer/core/integrate/stepped_integrator.h"
#include "tissue_trainer/core/solve/equilibrium.h"

namespace tt {

class QuasistaticIntegrator : public SteppedIntegrator {
 public:
  explicit QuasistaticIntegrator(EquilibriumParams params = {});
  const char* name() const override { return "quasistatic"; }
  bool needsStiffness() const override { return true; }

  const EquilibriumParams& params() const { return solver_.params; }
  // Of the last attempted frame (or piece of one).
  const EquilibriumReport& lastReport() const { return last_; }

 private:
  FrameStart beginFrame(System& system, double frameTime) override;
  StepAttempt attempt(System& system, const StepContext& step, StepReport& report) override;
  std::string accept(System& system, const StepContext& step) override;
  // Time-dependent loads are those of the step's end, where the equilibrium is solved.
  double stepUpdateTime(const StepContext& step) const override { return step.end; }

  EquilibriumSolver solver_;
  EquilibriumReport last_;
  Eigen::VectorXd x_, v_;
};

}  // namespace tt
