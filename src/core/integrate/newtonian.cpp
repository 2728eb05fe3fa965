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

StepAttempt NewtonianIntegrator::attempt(System& system, const StepContext& step, StepReport&) {
  const State& s = system.state;
  const double h = step.h;
  if (!hasHistory_) start(system, h);
  undampedForce(system, s, force_);
  const double h1 = params_.assumeEqualSteps ? h : previousStep_;  // the paper's Delta t
  const double eta = params_.assumeEqualSteps ? 1.0 : h / previousStep_;
  const auto m = system.mass.array();
  const auto gamma = system.damping.array();
  // Lazy coefficient expressions (no temporaries): Eq 11 solved for x+, per DOF.
  const auto lhs = (2.0 * m / h1 + gamma) / (eta * (eta + 1.0) * h1);
  const auto current = (2.0 * m / h1 - gamma * (eta - 1.0)) / (eta * h1);
  const auto previous = (2.0 * m / h1 - gamma * eta) / ((eta + 1.0) * h1);
  nextX_.resize(s.x.size());
  nextX_.array() = (force_.array() + current * s.x.array() - previous * previousX_.array()) / lhs;
  frozen_.clear();
  if (params_.forceThreshold > 0.0) freezeLowForceNodes(system);

  // Second-order backward difference through x-, x, x+ with the actual steps.
  const double a = previousStep_, b = h;
  nextV_ = (nextX_ * ((2.0 * b + a) / (b * (a + b))) - s.x * ((a + b) / (a * b)) +
            previousX_ * (b / (a * (a + b))));
  for (int node : frozen_) nextV_.segment<3>(3 * node).setZero();
  return {};
}

std::string NewtonianIntegrator::accept(System& system, const StepContext& step) {
  State& s = system.state;
  previousX_.swap(s.x);
  s.x.swap(nextX_);
  s.v.swap(nextV_);
  previousStep_ = step.h;
  s.t = step.end;
  system.prescribe(s.t, s.x, s.v);
  return "";
}

void NewtonianIntegrator::freezeLowForceNodes(const System& system) {
  const State& s = system.state;
  const double threshold2 = params_.forceThreshold * params_.forceThreshold;
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

NewtonianIntegrator::NewtonianIntegrator(NewtonianParams params)
    : SteppedIntegrator(
          std::make_unique<FixedStepControl>(FixedStepControl::ofLength(params.substep))),
      params_(params) {}

FrameStart NewtonianIntegrator::beginFrame(System& system, double) {
  if (!continuesFrom(system.state)) hasHistory_ = false;  // start() at the first step
  startPrevious_ = previousX_;
  startStep_ = previousStep_;
  return {};
}

// The history goes back to the frame's start, so the next frame continues from there.
void NewtonianIntegrator::abandonFrame(const System& system) {
  previousX_ = startPrevious_;
  previousStep_ = startStep_;
  last_ = system.state;
}

}  // namespace tt
