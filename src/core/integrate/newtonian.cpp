#include "tissue_trainer/core/integrate/newtonian.h"

#include "frame_guard.h"

namespace tt {

bool NewtonianIntegrator::continuesFrom(const State& s) const {
  return hasHistory_ && s.t == last_.t && s.x.size() == last_.x.size() &&
         previousX_.size() == s.x.size() && s.x == last_.x && s.v == last_.v;
}

// Every force except the damping, which the scheme treats through its gamma terms.
static void undampedForce(const System& system, const State& s, Eigen::VectorXd& f) {
  system.computeForce(s.x, s.v, f);
  f += system.damping.cwiseProduct(s.v);
}

// Fictitious previous position from the Taylor expansion Eq A.2 at the current step size.
void NewtonianIntegrator::start(const System& system, double h) {
  const State& s = system.state;
  undampedForce(system, s, force_);
  const Eigen::ArrayXd accel =
      (force_ - system.damping.cwiseProduct(s.v)).array() / system.mass.array();
  previousX_ = (s.x.array() - h * s.v.array() + 0.5 * h * h * accel).matrix();
  previousStep_ = h;
  hasHistory_ = true;
}

void NewtonianIntegrator::substep(System& system, double h, double endTime) {
  State& s = system.state;
  undampedForce(system, s, force_);
  const double h1 = params.assumeEqualSteps ? h : previousStep_;  // seed's Delta t
  const double eta = params.assumeEqualSteps ? 1.0 : h / previousStep_;
  const auto m = system.mass.array();
  const auto gamma = system.damping.array();
  // Lazy coefficient expressions (no temporaries): Eq 11 solved for x+, per DOF.
  const auto lhs = (2.0 * m / h1 + gamma) / (eta * (eta + 1.0) * h1);
  const auto current = (2.0 * m / h1 - gamma * (eta - 1.0)) / (eta * h1);
  const auto previous = (2.0 * m / h1 - gamma * eta) / ((eta + 1.0) * h1);
  nextX_.resize(s.x.size());
  nextX_.array() = (force_.array() + current * s.x.array() - previous * previousX_.array()) / lhs;
  frozen_.clear();
  if (params.forceThreshold > 0.0) freezeLowForceNodes(system);

  // Second-order backward difference through x-, x, x+ with the actual steps.
  const double a = previousStep_, b = h;
  s.v = (nextX_ * ((2.0 * b + a) / (b * (a + b))) - s.x * ((a + b) / (a * b)) +
         previousX_ * (b / (a * (a + b))));
  for (int node : frozen_) s.v.segment<3>(3 * node).setZero();
  previousX_.swap(s.x);
  s.x.swap(nextX_);
  previousStep_ = h;
  s.t = endTime;
  system.prescribe(s.t, s.x, s.v);
}

void NewtonianIntegrator::freezeLowForceNodes(const System& system) {
  const State& s = system.state;
  const double threshold2 = params.forceThreshold * params.forceThreshold;
  for (int node = 0; node < system.numNodes(); ++node) {
    const int dof = 3 * node;
    if (system.isConstrained[dof] && system.isConstrained[dof + 1] && system.isConstrained[dof + 2])
      continue;
    const Eigen::Vector3d net =
        force_.segment<3>(dof) - system.damping.segment<3>(dof).cwiseProduct(s.v.segment<3>(dof));
    if (net.squaredNorm() >= threshold2) continue;
    nextX_.segment<3>(dof) = s.x.segment<3>(dof);
    frozen_.push_back(node);
  }
  frozenNodeSteps_ += static_cast<long>(frozen_.size());
}

StepReport NewtonianIntegrator::advance(System& system, double frameTime) {
  StepReport report;
  detail::FrameGuard guard(system.state);
  const int n = detail::equalSubsteps(frameTime, currentStep(params.substep));
  const double h = frameTime / n;
  if (!continuesFrom(system.state)) start(system, h);
  const Eigen::VectorXd startPrevious = previousX_;
  const double startStep = previousStep_;

  for (int i = 0; i < n; ++i) {
    substep(system, h, detail::substepEnd(guard.start().t, frameTime, i, n));
    if (!detail::FrameGuard::finite(system.state)) {
      guard.restore(system.state, report,
                    "newtonian: non-finite state at t = " + std::to_string(system.state.t) +
                        " (step " + std::to_string(h) + " s; explicit limit h < 2/omega_max)");
      previousX_ = startPrevious;
      previousStep_ = startStep;
      break;
    }
    ++report.substeps;
    report.lastStep = h;
  }
  last_ = system.state;
  guard.finish(report);
  return report;
}

}  // namespace tt
