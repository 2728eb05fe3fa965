#pragma once
// The variable-step explicit "Newtonian" scheme of Jeffrey, "A non-linear anisotropic Finite
// Element Method for surgical simulation" (Eqs 10-11, Appendix A): a two-step
// central-difference method on positions for m x'' = F - gamma x'.
//
// With h_prev the previous step and h = eta * h_prev the new one (Jeffrey's Delta t and
// eta Delta t), Eq 11 gives, per DOF,
//   (2m/(eta(eta+1)h_prev^2) + gamma/(eta(eta+1)h_prev)) x+ = F
//       + (2m/(eta h_prev^2) - gamma(eta-1)/(eta h_prev)) x
//       - (2m/((eta+1)h_prev^2) - gamma eta/((eta+1)h_prev)) x-
// where F is every force except the damping (models + external). This is exactly Eq 10 with
// the physical damping force -gamma v (the Appendix A velocity and acceleration formulas
// substituted into m a + gamma v = F), so it is what is implemented.
//
// Damping sign: the equal-step form printed as Eq A.5 is Eq 11 at eta = 1 with gamma
// replaced by -gamma, i.e. it integrates Picinbono's Eq A.3 (m a = F + gamma v), which pumps
// energy in. The option assumeEqualSteps uses the eta = 1 form with the physical sign:
//   (m/h^2 + gamma/(2h)) x+ = F + 2m/h^2 x - (m/h^2 - gamma/(2h)) x-
// (printed A.5 with gamma -> -gamma), taking h as the current step even when the previous
// step differed, as Picinbono's scheme does. It is first order at best when steps change.
//
// The scheme carries the previous position between frames. It restarts (second-order
// Taylor start, Eq A.2 with a = M^-1 (F - gamma v)) when the system's state was changed
// from outside since the last frame. The velocity written to the state is the second-order
// backward difference through the last three positions (exact for quadratics, any steps).
// Stable for undamped linear problems when h < 2 / omega_max.
//
// Force threshold (Jeffrey's report, Sec. 3; off by default): a free node whose net force
// |F_i - gamma_i v_i| (Eq 10's right-hand side, i.e. m a) is below forceThreshold at the start
// of a substep is not propagated: it keeps its position and its velocity is set to zero for
// that step. It saves only the per-node update here (the force is still evaluated for every
// tet), and it changes the dynamics: see bench_force_threshold for the error it costs.
#include <Eigen/Core>
#include <vector>

#include "tissue_trainer/core/integrate/stepped_integrator.h"

namespace tt {

struct NewtonianParams {
  double substep = 1e-3;          // s; a frame is split into equal substeps no longer than this
  bool assumeEqualSteps = false;  // Picinbono's eta = 1 form (with the physical damping sign)
  double forceThreshold = 0.0;    // N; > 0: nodes with a smaller net force are not propagated
};

class NewtonianIntegrator : public SteppedIntegrator {
 public:
  explicit NewtonianIntegrator(NewtonianParams params = {});
  const char* name() const override { return "newtonian"; }
  const NewtonianParams& params() const { return params_; }

  // Forgets the previous position: the next step starts from the state's x and v.
  void restart() { hasHistory_ = false; }

  // Node-steps skipped by the force threshold since construction (free nodes only).
  long frozenNodeSteps() const { return frozenNodeSteps_; }

 private:
  FrameStart beginFrame(System& system, double frameTime) override;
  StepAttempt attempt(System& system, const StepContext& step, StepReport& report) override;
  std::string accept(System& system, const StepContext& step) override;
  void endFrame(System& system) override { last_ = system.state; }
  void abandonFrame(const System& system) override;
  std::string instabilityHint() const override { return "; explicit limit h < 2/omega_max"; }

  bool continuesFrom(const State& s) const;
  void start(const System& system, double h);
  // Lists the free nodes under the force threshold in frozen_ and keeps their position in
  // nextX_ (their velocity is zeroed after the update).
  void freezeLowForceNodes(const System& system);

  NewtonianParams params_;
  bool hasHistory_ = false;
  Eigen::VectorXd previousX_;  // position one step back
  double previousStep_ = 0.0;
  long frozenNodeSteps_ = 0;
  State last_;                 // the state this integrator left behind
  Eigen::VectorXd startPrevious_;  // previousX_ at the start of the frame
  double startStep_ = 0.0;
  Eigen::VectorXd force_, nextX_, nextV_;
  std::vector<int> frozen_;
};

}  // namespace tt
