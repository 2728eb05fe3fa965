// The pseudo-time recovery of the equilibrium solver (equilibrium.h, PseudoTimeRecovery).
#include <algorithm>
#include <cmath>

#include "tissue_trainer/core/solve/equilibrium.h"

namespace tt {

bool PseudoTimeRecovery::assemble(const System& system, const Eigen::VectorXd& x,
                                  double& meanDiagonal) {
  if (!assembleConstrainedNegativeStiffness(system, x, A_, diagonal_)) return false;
  stiffnessDiagonal_.resize(A_.rows());
  meanDiagonal = 0.0;
  int free = 0;
  for (int row = 0; row < A_.rows(); ++row) {
    stiffnessDiagonal_[row] = A_.valuePtr()[diagonal_[row]];
    if (!system.isConstrained[row]) {
      meanDiagonal += std::abs(stiffnessDiagonal_[row]);
      ++free;
    }
  }
  meanDiagonal = free > 0 ? meanDiagonal / free : 0.0;
  return true;
}

bool PseudoTimeRecovery::solveStep(const System& system, const EquilibriumParams& params,
                                   double tau, const Eigen::VectorXd& f,
                                   EquilibriumReport& report) {
  double* a = A_.valuePtr();
  shiftedDiagonal_ = stiffnessDiagonal_;
  for (int row = 0; row < A_.rows(); ++row)
    if (!system.isConstrained[row]) shiftedDiagonal_[row] += weight_[row] / tau;
  for (int row = 0; row < A_.rows(); ++row) a[diagonal_[row]] = shiftedDiagonal_[row];
  // A new factor for every step: the mass term changes the matrix from one step to the next.
  LinearSolveSettings settings = params.linearSolve();
  settings.refactorIterations = 0;
  linear_.configure(settings);
  dx_.setZero(f.size());
  const LinearSolveReport solved = linear_.solve(A_, f, dx_);
  report.linearIterations += solved.iterations;
  return !solved.refused && !solved.lostCurvature;
}

bool PseudoTimeRecovery::tryStep(const System& system, const EquilibriumParams& params,
                                 double& tau, Eigen::VectorXd& x, Eigen::VectorXd& f,
                                 double& residual, EquilibriumReport& report) {
  if (!solveStep(system, params, tau, f, report)) return false;
  trial_ = x + dx_;
  system.computeForce(trial_, zeroVelocity_, trialF_);
  system.zeroConstrained(trialF_);
  const double r = trialF_.stableNorm();
  if (!std::isfinite(r) || r > kRejectGrowth * residual) return false;
  x.swap(trial_);
  f.swap(trialF_);
  tau *= std::clamp(residual / r, 1.0 / kGrowth, kGrowth);
  residual = r;
  ++report.pseudoTimeSteps;
  report.residual = residual;
  report.residualHistory.push_back(residual);
  return true;
}

bool PseudoTimeRecovery::stepsLeft(const EquilibriumParams& params,
                                   const EquilibriumReport& report) const {
  return report.pseudoTimeSteps + report.rejectedPseudoTimeSteps < params.maxPseudoTimeSteps;
}

int PseudoTimeRecovery::invertedElements(const System& system, const Eigen::VectorXd& x) {
  const int elements = system.mesh.numTets() + system.mesh.numHexes();
  if (checkedMesh_ != &system.mesh || checkedElements_ != elements) {
    corruptCheck_ = CorruptElementCheck(system.mesh, HexSplit::kSix);
    checkedMesh_ = &system.mesh;
    checkedElements_ = elements;
  }
  if (corruptCheck_.empty()) return 0;
  const Eigen::Map<const Eigen::Matrix3Xd> nodes(x.data(), 3, system.numNodes());
  return static_cast<int>(corruptCheck_.find(nodes, 0.0).size());
}

void PseudoTimeRecovery::start() { settledInverted_ = 0; }

bool PseudoTimeRecovery::wanted(const System& system, const EquilibriumParams& params,
                                const Eigen::VectorXd& x, const EquilibriumReport& report) {
  return stepsLeft(params, report) && invertedElements(system, x) > settledInverted_;
}

bool PseudoTimeRecovery::run(const System& system, const EquilibriumParams& params,
                             double target, Eigen::VectorXd& x, Eigen::VectorXd& f,
                             double& residual, EquilibriumReport& report) {
  if (!stepsLeft(params, report)) return false;
  ++report.recoveries;
  zeroVelocity_.setZero(x.size());
  // The masses of the free DOFs; the mean free mass where a DOF has none (1 kg if none has).
  weight_ = system.mass;
  double meanMass = 0.0;
  int massive = 0;
  for (int i = 0; i < weight_.size(); ++i)
    if (!system.isConstrained[i] && weight_[i] > 0.0) {
      meanMass += weight_[i];
      ++massive;
    }
  meanMass = massive > 0 ? meanMass / massive : 1.0;
  for (int i = 0; i < weight_.size(); ++i)
    if (!(weight_[i] > 0.0)) weight_[i] = meanMass;

  double tau = 0.0;
  int newtonSizedSteps = 0;
  bool moved = true;  // the matrix is assembled anew only where a step was taken
  while (stepsLeft(params, report)) {
    if (moved) {
      double meanDiagonal = 0.0;
      if (!assemble(system, x, meanDiagonal)) return false;
      // Without stiffness the steps are the masses' alone: 1 N/m stands in for its scale.
      if (!(meanDiagonal > 0.0)) meanDiagonal = 1.0;
      if (tau == 0.0) tau = meanMass / (params.pseudoTimeInitialRatio * meanDiagonal);
      if (meanMass / tau <= kHandOff * meanDiagonal) {
        // The steps have become Newton's. Elements still inverted after kSettleSteps of them
        // are part of the equilibrium (an inversion-handled law pushes back on them with a
        // finite force): Newton goes on from here and the recovery is wanted again only for
        // more of them.
        const int inverted = invertedElements(system, x);
        if (inverted == 0) return true;
        if (++newtonSizedSteps >= kSettleSteps) {
          settledInverted_ = inverted;
          return true;
        }
      }
    }
    moved = tryStep(system, params, tau, x, f, residual, report);
    if (!moved) {
      ++report.rejectedPseudoTimeSteps;
      tau *= 0.25;
    } else if (residual <= target) {
      return true;
    }
  }
  return false;
}

}  // namespace tt
