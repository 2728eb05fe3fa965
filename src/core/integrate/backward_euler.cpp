#include "tissue_trainer/core/integrate/backward_euler.h"

#include <algorithm>
#include <cmath>

#include "frame_guard.h"

namespace tt {

namespace {

// stableNorm: a body nearly at rest has residuals whose squares underflow.
double freeNorm(const System& system, Eigen::VectorXd r) {
  system.zeroConstrained(r);
  return r.stableNorm();
}

}  // namespace

void BackwardEulerIntegrator::buildMatrix(const System& system, double h,
                                          const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                                          SparseMatrix& A, bool projected) {
  const bool differences = finiteDifferences();
  if (differences)
    differenceJacobians(system, h, x, v, A);
  else
    system.assembleStiffness(x, A, -h * h, projected);  // in place: no copy of K
  if (diagonal_.size() != static_cast<size_t>(A.rows())) {
    diagonal_.assign(A.rows(), -1);
    for (int row = 0; row < A.outerSize(); ++row)
      for (SparseMatrix::InnerIterator it(A, row); it; ++it)
        if (it.col() == row) diagonal_[row] = static_cast<int>(&it.valueRef() - A.valuePtr());
  }
  double* a = A.valuePtr();
  for (int row = 0; row < A.rows(); ++row)
    a[diagonal_[row]] += system.mass[row] + (differences ? 0.0 : h * system.damping[row]);
  if (!differences) {
    if (!system.hasVelocityJacobian()) return;
    system.assembleVelocityJacobian(x, v, C_);
  }
  const double* c = C_.valuePtr();  // the same pattern as A
  for (Eigen::Index i = 0; i < C_.nonZeros(); ++i) a[i] -= h * c[i];
}

void BackwardEulerIntegrator::differenceJacobians(const System& system, double h,
                                                  const Eigen::VectorXd& x,
                                                  const Eigen::VectorXd& v, SparseMatrix& A) {
  if (!differences_ || !differences_->matches(system))
    differences_ = std::make_unique<FiniteDifferenceJacobian>(system, params.finiteDifference);
  system.computeForce(x, v, differenceForce_);
  differences_->positions(system, x, v, differenceForce_, -h * h, A);
  differences_->velocities(system, x, v, differenceForce_, 1.0, C_);
  ++diagnostics_.jacobianForceEvaluations;  // differenceForce_
  diagnostics_.jacobianForceEvaluations += 2 * differences_->groups();
}

void BackwardEulerIntegrator::velocityTermTimes(const System& system, double h,
                                                const Eigen::VectorXd& v,
                                                Eigen::VectorXd& out) const {
  if (finiteDifferences()) {
    out.noalias() = -h * (C_ * v);
    return;
  }
  out = h * system.damping.cwiseProduct(v);
  if (system.hasVelocityJacobian()) out.noalias() -= h * (C_ * v);
}

int BackwardEulerIntegrator::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  // Solved for x / s against b / s with s = max |b_i|: a body that has nearly come to rest
  // under strong damping has a right side so small that |b|^2 and the CG products underflow
  // (to 0 / 0, or to a zero step that stops the damping).
  const double scale = b.lpNorm<Eigen::Infinity>();
  if (scale == 0.0) {
    linear_.solve(A_, b, x);  // x = 0
    copyLinearDiagnostics();
    return 0;
  }
  unitB_ = b / scale;
  x /= scale;
  if (!x.allFinite()) x.setZero();
  const int iterations = linear_.solve(A_, unitB_, x, this).iterations;
  copyLinearDiagnostics();
  x *= scale;
  return iterations;
}

void BackwardEulerIntegrator::copyLinearDiagnostics() {
  static_cast<LinearSolveDiagnostics&>(diagnostics_) = linear_.diagnostics();
}

bool BackwardEulerIntegrator::canProject() const {
  return !finiteDifferences() && stepSystem_ && stepSystem_->hasProjectedStiffness();
}

const SparseMatrix& BackwardEulerIntegrator::projectedMatrix() {
  const System& system = *stepSystem_;
  buildMatrix(system, stepH_, system.state.x, system.state.v, projectedA_, true);
  system.constrainMatrix(projectedA_);
  return projectedA_;
}

const SparseMatrix& BackwardEulerIntegrator::restMatrix() {
  const System& system = *stepSystem_;
  const Eigen::Map<const Eigen::VectorXd> rest(system.mesh.rest.data(), system.mesh.rest.size());
  buildMatrix(system, stepH_, rest, Eigen::VectorXd::Zero(rest.size()), restA_);
  system.constrainMatrix(restA_);
  return restA_;
}

LinearSolveSettings BackwardEulerParams::linearSolve() const {
  LinearSolveSettings s;
  s.method = linearSolver;
  s.gmresRestart = gmresRestart;
  s.tolerance = linearTolerance;
  s.maxIterations = linearMaxIterations;
  s.preconditioner = preconditioner;
  s.refactorIterations = refactorIterations;
  s.backgroundRefactor = backgroundRefactor;
  s.choleskyBackend = choleskyBackend;
  s.amg = amg;
  return s;
}

void BackwardEulerParams::setLinearSolve(const LinearSolveSettings& s) {
  linearSolver = s.method;
  gmresRestart = s.gmresRestart;
  linearTolerance = s.tolerance;
  linearMaxIterations = s.maxIterations;
  preconditioner = s.preconditioner;
  refactorIterations = s.refactorIterations;
  backgroundRefactor = s.backgroundRefactor;
  choleskyBackend = s.choleskyBackend;
  amg = s.amg;
}

HalvingDoublingParams iterationStepControl(const BackwardEulerParams& params) {
  HalvingDoublingParams c;
  c.quantity = HalvingDoublingParams::Quantity::kIterations;
  c.lower = params.lowerIterations;
  // The controller halves above `upper`; the chapter halves when the count reaches the upper
  // limit, which for whole counts is above upperIterations - 1/2.
  c.upper = params.upperIterations - 0.5;
  c.rejectAboveUpper = true;
  c.keepAtMinStep = true;
  c.initialStep = params.initialStep;
  c.minStep = params.minStep;
  c.maxStep = params.maxStep;
  return c;
}

namespace {

std::unique_ptr<StepSizeController> stepControlOf(const BackwardEulerParams& params) {
  if (params.adaptive)
    return std::make_unique<HalvingDoublingControl>(iterationStepControl(params));
  return std::make_unique<FixedStepControl>(FixedStepControl::ofCount(params.substeps));
}

}  // namespace

BackwardEulerIntegrator::BackwardEulerIntegrator(BackwardEulerParams params)
    : BackwardEulerIntegrator(params, stepControlOf(params)) {}

BackwardEulerIntegrator::BackwardEulerIntegrator(BackwardEulerParams params,
                                                 std::unique_ptr<StepSizeController> control)
    : SteppedIntegrator(std::move(control)),
      params(params),
      linear_(params.linearSolve(), LinearSolveRule::timeStepping()) {}

FrameStart BackwardEulerIntegrator::beginFrame(System& system, double) {
  FrameStart start;
  if (needsStiffness() && !system.hasStiffness())
    start.failure = "backward_euler: every force model must provide its stiffness";
  return start;
}

StepAttempt BackwardEulerIntegrator::attempt(System& system, const StepContext& step,
                                             StepReport& report) {
  StepAttempt out;
  const auto failed = [&out](StepStatus status, std::string why) {
    out.status = status;
    out.failure = std::move(why);
    return out;
  };
  linear_.configure(params.linearSolve());
  linear_.installFinishedFactor();
  const State& s = system.state;
  const double h = step.h, endTime = step.end;
  const int linearBefore = report.linearIterations;
  const Eigen::Index n = s.x.size();
  system.computeForce(s.x, s.v, f_);
  ++report.jacobians;
  buildMatrix(system, h, s.x, s.v, A_);

  // Constrained DOFs: dv that lands x + h (v + dv) on the prescribed position at t + h.
  targetX_ = s.x;
  targetV_ = s.v;
  system.prescribe(endTime, targetX_, targetV_);
  constrainedDv_.setZero(n);
  for (int dof : system.constrainedDofs)
    constrainedDv_[dof] = (targetX_[dof] - s.x[dof]) / h - s.v[dof];

  // h (f + h K v), with h^2 K v = (M + V) v - A v read off the unconstrained A, V its velocity
  // part.
  velocityTermTimes(system, h, s.v, rhs_);
  rhs_ += h * f_ + system.mass.cwiseProduct(s.v);
  rhs_.noalias() -= A_ * s.v;
  // Only moving constrained DOFs (controlled nodes) couple into the free ones.
  if (constrainedDv_.lpNorm<Eigen::Infinity>() > 0.0) rhs_.noalias() -= A_ * constrainedDv_;
  for (int dof : system.constrainedDofs) rhs_[dof] = constrainedDv_[dof];
  if (!rhs_.allFinite() || !Eigen::Map<const Eigen::VectorXd>(A_.valuePtr(), A_.nonZeros())
                               .allFinite()) {
    return failed(StepStatus::kFailed,
                  "backward_euler: non-finite force or stiffness at t = " + std::to_string(s.t));
  }
  system.constrainMatrix(A_);
  stepSystem_ = &system;
  stepH_ = h;
  linear_.ensureFactor(A_, this);
  copyLinearDiagnostics();
  if (!params.warmStart || dv_.size() != n) dv_.setZero(n);
  else if (lastStep_ > 0.0 && h != lastStep_) dv_ *= h / lastStep_;  // dv grows with h
  lastStep_ = h;
  for (int dof : system.constrainedDofs) dv_[dof] = constrainedDv_[dof];
  report.linearIterations += solve(rhs_, dv_);
  int solves = 1;

  bool converged = true;
  if (params.newtonIterations > 1) {
    const double scale = freeNorm(system, rhs_);
    converged = false;
    while (true) {
      v1_ = s.v + dv_;
      x1_ = s.x + h * v1_;
      for (int dof : system.constrainedDofs) {
        x1_[dof] = targetX_[dof];
        v1_[dof] = targetV_[dof];
      }
      system.computeForce(x1_, v1_, f_);
      residual_ = system.mass.cwiseProduct(dv_) - h * f_;
      system.zeroConstrained(residual_);
      if (residual_.stableNorm() <= params.newtonTolerance * scale) {
        converged = true;
        break;
      }
      if (!residual_.allFinite()) {
        return failed(StepStatus::kFailed,
                      "backward_euler: non-finite force in Newton iteration at t = " +
                          std::to_string(s.t));
      }
      if (solves >= params.newtonIterations) break;
      ++report.jacobians;
      buildMatrix(system, h, x1_, v1_, A_);
      system.constrainMatrix(A_);
      correction_.setZero(n);
      report.linearIterations += solve(-residual_, correction_);
      dv_ += correction_;
      ++solves;
    }
  }
  report.newtonIterations += solves;
  if (!converged) {
    ++diagnostics_.unconvergedNewton;
    if (params.requireConvergence) {
      return failed(StepStatus::kNotConverged,
                    "backward_euler: Newton did not converge in " +
                        std::to_string(params.newtonIterations) + " iterations at t = " +
                        std::to_string(s.t));
    }
  }

  // Local error of backward Euler in position: h^2/2 x'' ~ h/2 dv (free DOFs, max norm).
  correction_ = 0.5 * h * dv_;
  system.zeroConstrained(correction_);
  out.measure.error = correction_.lpNorm<Eigen::Infinity>();
  out.measure.iterations = report.linearIterations - linearBefore;
  return out;
}

std::string BackwardEulerIntegrator::accept(System& system, const StepContext& step) {
  State& s = system.state;
  s.v += dv_;
  s.x += step.h * s.v;
  s.t = step.end;
  system.prescribe(s.t, s.x, s.v);
  return "";
}

}  // namespace tt
