#include "tissue_trainer/core/solve/equilibrium.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace tt {

namespace {

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

// y = -df/dx v over the free DOFs by a forward difference of the force at x (f its free force
// there), the constrained rows identity. The difference step is the usual
// sqrt(epsilon) (1 + |x|) / |v| (Knoll and Keyes, Sec. 2.2).
class NegativeForceDerivative final : public LinearOperator {
 public:
  NegativeForceDerivative(const System& system, const Eigen::VectorXd& x,
                          const Eigen::VectorXd& f, const Eigen::VectorXd& zeroVelocity,
                          Eigen::VectorXd& shiftedX, Eigen::VectorXd& shiftedF, int& evaluations)
      : system_(system), x_(x), f_(f), zeroVelocity_(zeroVelocity), shiftedX_(shiftedX),
        shiftedF_(shiftedF), evaluations_(evaluations), xScale_(1.0 + x.norm()) {}

  Eigen::Index size() const override { return x_.size(); }

  void apply(const Eigen::VectorXd& v, Eigen::VectorXd& y) const override {
    y = v;
    shiftedX_ = v;
    system_.zeroConstrained(shiftedX_);
    const double length = shiftedX_.norm();
    if (!(length > 0.0)) return;
    const double h = std::sqrt(std::numeric_limits<double>::epsilon()) * xScale_ / length;
    shiftedX_ = x_ + h * shiftedX_;
    system_.computeForce(shiftedX_, zeroVelocity_, shiftedF_);
    ++evaluations_;
    for (Eigen::Index i = 0; i < y.size(); ++i)
      if (!system_.isConstrained[i]) y[i] = (f_[i] - shiftedF_[i]) / h;
  }

 private:
  const System& system_;
  const Eigen::VectorXd& x_;
  const Eigen::VectorXd& f_;
  const Eigen::VectorXd& zeroVelocity_;
  Eigen::VectorXd& shiftedX_;
  Eigen::VectorXd& shiftedF_;
  int& evaluations_;
  double xScale_;
};

}  // namespace

const char* stopName(EquilibriumStop stop) {
  switch (stop) {
    case EquilibriumStop::kConverged: return "converged";
    case EquilibriumStop::kIterationLimit: return "iteration limit";
    case EquilibriumStop::kLineSearchFailed: return "line search failed";
    case EquilibriumStop::kNonFiniteForce: return "non-finite force";
    case EquilibriumStop::kNoStiffness: return "no stiffness";
    case EquilibriumStop::kRecoveryFailed: return "recovery failed";
  }
  return "unknown";
}

EquilibriumSolver::EquilibriumSolver(EquilibriumParams p) : params(p) {}

double EquilibriumSolver::residualAt(const System& system, const Eigen::VectorXd& x,
                                     Eigen::VectorXd& f, double& potential,
                                     EquilibriumReport& report) const {
  // The force pass returns the models' energies (ForceModel::addForce).
  const double energy = system.computeForce(x, zeroVelocity_, f);
  ++report.forceEvaluations;
  potential = !hasEnergy_           ? std::numeric_limits<double>::quiet_NaN()
              : holdsFollowerLoads_ ? energy - system.externalForce.dot(x) - heldLoad_.dot(x)
                                    : energy - system.externalForce.dot(x);
  system.zeroConstrained(f);
  return f.stableNorm();  // a body nearly at rest: squares that underflow
}

bool EquilibriumSolver::conjugateGradientSolve(const Preconditioner& M, EquilibriumReport& report) {
  const SolveSettings settings{params.linearTolerance, params.linearMaxIterations, 30};
  dx_.setZero(f_.size());
  const SolveReport solved = conjugateGradients(MatrixOperator(A_), f_, dx_, M, settings, krylov_);
  report.linearIterations += solved.iterations;
  return solved.outcome != SolveOutcome::kNonPositiveCurvature;
}

bool EquilibriumSolver::unshiftedDirection(EquilibriumReport& report) {
  linear_.configure(params.linearSolve());
  const int factorsBefore = linear_.diagnostics().factorizations;
  dx_.setZero(f_.size());
  const LinearSolveReport solved = linear_.solve(A_, f_, dx_);
  report.linearIterations += solved.iterations;
  report.factorizations += linear_.diagnostics().factorizations - factorsBefore;
  // An unconverged solve still gives an inexact Newton direction; the line search judges it.
  return !solved.refused && !solved.lostCurvature;
}

LinearSolveSettings EquilibriumParams::linearSolve() const {
  LinearSolveSettings s;
  s.tolerance = linearTolerance;
  s.maxIterations = linearMaxIterations;
  s.preconditioner = preconditioner;
  s.refactorIterations = refactorIterations;
  return s;
}

void EquilibriumParams::setLinearSolve(const LinearSolveSettings& s) {
  linearTolerance = s.tolerance;
  linearMaxIterations = s.maxIterations;
  preconditioner = s.preconditioner;
  refactorIterations = s.refactorIterations;
}

void EquilibriumSolver::scaledForceDirection() {
  dx_ = f_.cwiseQuotient(diagonalValues_.cwiseAbs().cwiseMax(1e-300));
}

bool assembleConstrainedNegativeStiffness(const System& system, const Eigen::VectorXd& x,
                                          SparseMatrix& A, std::vector<int>& diagonalOffsets) {
  system.assembleStiffness(x, A, -1.0);
  if (!Eigen::Map<const Eigen::VectorXd>(A.valuePtr(), A.nonZeros()).allFinite()) return false;
  system.constrainMatrix(A);
  if (diagonalOffsets.size() != static_cast<size_t>(A.rows())) {
    diagonalOffsets.assign(A.rows(), -1);
    for (int row = 0; row < A.outerSize(); ++row)
      for (SparseMatrix::InnerIterator it(A, row); it; ++it)
        if (it.col() == row) diagonalOffsets[row] = static_cast<int>(&it.valueRef() - A.valuePtr());
  }
  return true;
}

bool EquilibriumSolver::newtonDirection(const System& system, const Eigen::VectorXd& x,
                                        EquilibriumReport& report) {
  if (!assembleConstrainedNegativeStiffness(system, x, A_, diagonal_)) return false;
  double* a = A_.valuePtr();
  diagonalValues_.resize(A_.rows());
  for (int row = 0; row < A_.rows(); ++row) diagonalValues_[row] = a[diagonal_[row]];
  if (unshiftedDirection(report)) return true;

  // -K is not positive definite here: -K + mu I over the free DOFs, mu growing tenfold.
  double meanDiagonal = 0.0;
  int free = 0;
  for (int row = 0; row < A_.rows(); ++row)
    if (!system.isConstrained[row]) {
      meanDiagonal += std::abs(diagonalValues_[row]);
      ++free;
    }
  meanDiagonal = free > 0 ? meanDiagonal / free : 1.0;
  // A kept factor (of an earlier, positive definite matrix) preconditions the shifted solves
  // better than Jacobi; CG meets the non-positive curvature all the same.
  const Preconditioner* factor = linear_.factor(A_.rows());
  double applied = 0.0, mu = params.shiftFraction * meanDiagonal;
  for (int k = 0; k < params.maxShifts; ++k, mu *= 10.0) {
    for (int row = 0; row < A_.rows(); ++row)
      if (!system.isConstrained[row]) a[diagonal_[row]] += mu - applied;
    applied = mu;
    for (int row = 0; row < A_.rows(); ++row) diagonalValues_[row] = a[diagonal_[row]];
    const bool jacobiUsable =
        shiftedJacobi_.setDiagonal(diagonalValues_) && shiftedJacobi_.positive();
    if ((factor || jacobiUsable) &&
        conjugateGradientSolve(factor ? *factor : shiftedJacobi_, report)) {
      ++report.shiftedSolves;
      return true;
    }
  }
  ++report.gradientSteps;
  scaledForceDirection();
  return true;
}

// The shortest step (of Newton's: three halvings) whose energy change within round-off is
// judged by the residual (lineSearch). On the muscle block of test_equilibrium_stall.cpp 1/64
// still let Newton creep (frame 159 failed); 1/8 and 1/2 gave the same outcomes on the
// stiff cells of the quasistatic stability grid as the unbounded test.
constexpr double kShortestRoundOffStep = 1.0 / 8.0;

bool EquilibriumSolver::lineSearch(const System& system, Eigen::VectorXd& x, double& residual,
                                   EquilibriumReport& report, Merit merit) {
  const bool byEnergy = hasEnergy_ && merit == Merit::kEnergy;
  const double energy0 = potential_;
  const double slope = f_.dot(dx_);  // -dPi/da at a = 0
  double step = 1.0;
  for (int k = 0; k <= params.maxLineSearchSteps; ++k, step *= 0.5) {
    trial_ = x + step * dx_;
    double energy;
    const double r = residualAt(system, trial_, trialF_, energy, report);
    if (!std::isfinite(r)) continue;
    bool accepted;
    if (byEnergy) {
      if (!std::isfinite(energy)) continue;
      // An energy change within the energy's round-off says nothing about the step: near the
      // solution it is judged by the residual. Not below kShortestRoundOffStep: a step cut
      // that short lands in the round-off where the energy refused the longer ones (at a
      // clamped element the force is not the energy's gradient); its residual moves by a
      // hair, and taken as progress such steps kept Newton creeping at one residual for all
      // its iterations and the recovery from starting.
      const bool roundOff = std::abs(energy - energy0) <=
                            1e-12 * std::max(std::abs(energy0), std::abs(energy));
      const bool armijo = energy <= energy0 - params.armijo * step * slope;
      accepted = roundOff ? step >= kShortestRoundOffStep && (armijo || r < residual) : armijo;
    } else {
      accepted = r <= (1.0 - params.armijo * step) * residual;
    }
    if (accepted) {
      x.swap(trial_);
      f_.swap(trialF_);
      potential_ = energy;
      residual = r;
      lastStep_ = step;
      return true;
    }
  }
  return false;
}

bool EquilibriumSolver::forceDerivativeDirection(const System& system, const Eigen::VectorXd& x,
                                                 EquilibriumReport& report) {
  const Preconditioner* M = linear_.factor(A_.rows());
  if (!M) {
    derivativeJacobi_.setDiagonal(diagonalValues_);  // the identity where an entry is zero
    M = &derivativeJacobi_;
  }
  int evaluations = 0;
  const NegativeForceDerivative derivative(system, x, f_, zeroVelocity_, differenceX_,
                                           differenceF_, evaluations);
  const SolveSettings settings{kDerivativeTolerance, kDerivativeIterations,
                               kDerivativeIterations};
  dx_ = stiffnessDx_;
  const SolveReport solved = gmres(derivative, f_, dx_, *M, settings, krylov_);
  report.forceEvaluations += evaluations;
  report.linearIterations += solved.iterations;
  // Far from kDerivativeTolerance (a preconditioner far from the derivative) the step is no
  // Newton step; within kDerivativeForcing it is an inexact one that still converges fast.
  return solved.relativeResidual <= kDerivativeForcing && dx_.allFinite();
}

// The step on the force's own derivative descends |f|^2 (f . (df/dx) dx = -|f|^2), not
// necessarily the energy, from which the force at a clamped element does not derive: its line
// search judges the residual.
bool EquilibriumSolver::derivativeStep(const System& system, Eigen::VectorXd& x,
                                       double& residual, EquilibriumReport& report) {
  if (!forceDerivativeDirection(system, x, report) ||
      !lineSearch(system, x, residual, report, Merit::kResidual))
    return false;
  ++report.derivativeSteps;
  return true;
}

bool EquilibriumSolver::takeStep(const System& system, Eigen::VectorXd& x, double& residual,
                                 EquilibriumReport& report) {
  stiffnessDx_ = dx_;
  const bool derivativeTried = onDerivative_;
  if (derivativeTried) {
    if (derivativeStep(system, x, residual, report)) return true;
    onDerivative_ = false;
    slowIterations_ = 0;
    dx_ = stiffnessDx_;
  }
  // Not a descent direction of the energy (an indefinite matrix CG did not notice):
  // the scaled force is.
  const bool gradient = hasEnergy_ && !(f_.dot(dx_) > 0.0);
  if (gradient) {
    ++report.gradientSteps;
    scaledForceDirection();
  }
  if (lineSearch(system, x, residual, report)) return true;
  if (!gradient) {
    ++report.gradientSteps;
    scaledForceDirection();
    if (lineSearch(system, x, residual, report)) return true;
  }
  // The energy refused both (at clamped elements the force is not its gradient): the force's
  // own derivative, unless it was just refused.
  return !derivativeTried && hasEnergy_ && derivativeStep(system, x, residual, report);
}

// An unshifted Newton step of a few units in the last place of the positions: the residual
// left is the round-off of the force (stiff tissue puts it above a tolerance in newtons), and
// no representable x reduces it further.
bool EquilibriumSolver::newtonStepBelowRoundOff(const Eigen::VectorXd& x) const {
  constexpr double kUnitsInLastPlace = 32.0;
  const double scale = x.lpNorm<Eigen::Infinity>();
  // A step with a NaN must not pass as converged (the max norm may skip the NaN).
  return scale > 0.0 && dx_.allFinite() &&
         dx_.lpNorm<Eigen::Infinity>() <=
             kUnitsInLastPlace * std::numeric_limits<double>::epsilon() * scale;
}

// The line search compares energies with the one kept from the last force pass; the
// pseudo-time steps move x without it.
double EquilibriumSolver::potentialAfterRecovery(const System& system, const Eigen::VectorXd& x,
                                                 EquilibriumReport& report) {
  double potential = 0.0;
  residualAt(system, x, f_, potential, report);
  return potential;
}

EquilibriumReport EquilibriumSolver::solve(const System& system, Eigen::VectorXd& x) {
  EquilibriumReport report;
  const auto stop = [&report](EquilibriumStop why, std::string text) {
    report.stop = why;
    report.reason = std::move(text);
    return report;
  };
  if (!system.hasStiffness())
    return stop(EquilibriumStop::kNoStiffness,
                "equilibrium: every force model must provide its stiffness");
  hasEnergy_ = std::all_of(system.models.begin(), system.models.end(),
                           [](const auto& m) { return m->hasEnergy() || m->isFollowerLoad(); });
  holdsFollowerLoads_ = std::any_of(system.models.begin(), system.models.end(),
                                    [](const auto& m) { return m->isFollowerLoad(); });
  zeroVelocity_.setZero(x.size());
  if (holdsFollowerLoads_) heldLoad_.setZero(x.size());
  slowIterations_ = 0;
  onDerivative_ = false;
  recovery_.start();
  double residual = residualAt(system, x, f_, potential_, report);
  report.initialResidual = report.residual = residual;
  report.residualHistory.push_back(residual);
  if (!std::isfinite(residual))
    return stop(EquilibriumStop::kNonFiniteForce, "equilibrium: non-finite force at the start");
  const double target =
      std::max(params.absoluteTolerance, params.relativeTolerance * report.initialResidual);
  while (residual > target) {
    if (report.newtonIterations >= params.maxNewtonIterations)
      return stop(EquilibriumStop::kIterationLimit,
                  "equilibrium: no convergence in " + std::to_string(params.maxNewtonIterations) +
                      " Newton iterations (residual " + number(residual) + " N, tolerance " +
                      number(target) + " N)");
    if (recovery_.wanted(system, params, x, report)) {
      if (!recovery_.run(system, params, target, x, f_, residual, report))
        return stop(EquilibriumStop::kRecoveryFailed,
                    "equilibrium: elements still inverted after " +
                        std::to_string(report.pseudoTimeSteps) + " pseudo-time steps (residual " +
                        number(residual) + " N, tolerance " + number(target) + " N)");
      potential_ = potentialAfterRecovery(system, x, report);
    }
    if (residual <= target) break;
    const int shiftedBefore = report.shiftedSolves;
    if (!newtonDirection(system, x, report))
      return stop(EquilibriumStop::kNonFiniteForce,
                  "equilibrium: non-finite stiffness at Newton iteration " +
                      std::to_string(report.newtonIterations + 1));
    if (report.shiftedSolves == shiftedBefore && newtonStepBelowRoundOff(x)) {
      x += dx_;  // the last, full step: what it gains in the digits of the displacement is kept
      residual = residualAt(system, x, f_, potential_, report);
      ++report.newtonIterations;
      report.residual = residual;
      report.residualHistory.push_back(residual);
      report.atRoundOff = true;
      break;
    }
    holdFollowerLoads(system, x);
    const double residualBefore = residual;
    if (!takeStep(system, x, residual, report)) {
      if (recovery_.run(system, params, target, x, f_, residual, report)) {
        potential_ = potentialAfterRecovery(system, x, report);
        continue;
      }
      return stop(EquilibriumStop::kLineSearchFailed,
                  "equilibrium: the line search found no decrease at Newton iteration " +
                      std::to_string(report.newtonIterations + 1) + " (residual " +
                      number(residual) + " N, tolerance " + number(target) + " N, " +
                      std::to_string(report.pseudoTimeSteps) + " pseudo-time steps after it)");
    }
    ++report.newtonIterations;
    report.residual = residual;
    report.residualHistory.push_back(residual);
    // Linear convergence on the stiffness's full steps switches to the force's derivative;
    // a derivative step that does no better switches back.
    const bool slow = residual > kLinearRate * residualBefore;
    slowIterations_ = slow && lastStep_ == 1.0 ? slowIterations_ + 1 : 0;
    if (onDerivative_ && slow) {
      onDerivative_ = false;
      slowIterations_ = 0;
    } else if (slowIterations_ >= kSlowIterations) {
      onDerivative_ = true;
    }
  }
  // A NaN residual is not above the tolerance either: it ends the loop, but is no equilibrium.
  if (!std::isfinite(residual))
    return stop(EquilibriumStop::kNonFiniteForce,
                "equilibrium: non-finite force after Newton iteration " +
                    std::to_string(report.newtonIterations));
  return report;
}

void EquilibriumSolver::holdFollowerLoads(const System& system, const Eigen::VectorXd& x) {
  if (!holdsFollowerLoads_) return;
  followerScratch_.setZero(x.size());
  for (const auto& m : system.models)
    if (m->isFollowerLoad()) m->addForce(x, zeroVelocity_, followerScratch_);
  potential_ += (heldLoad_ - followerScratch_).dot(x);
  heldLoad_.swap(followerScratch_);
}

void solveEquilibrium(System& system, const EquilibriumParams& params,
                      EquilibriumReport& report) {
  EquilibriumSolver solver(params);
  Eigen::VectorXd x = system.state.x;
  report = solver.solve(system, x);
  system.state.x = x;
  system.state.v.setZero(x.size());
}

EquilibriumReport solveEquilibrium(System& system, const EquilibriumParams& params) {
  EquilibriumReport report;
  solveEquilibrium(system, params, report);
  return report;
}

}  // namespace tt
