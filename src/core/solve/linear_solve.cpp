#include "tissue_trainer/core/solve/linear_solve.h"

namespace tt {

const char* methodName(LinearMethod method) {
  switch (method) {
    case LinearMethod::kPcg: return "pcg";
    case LinearMethod::kGmres: return "gmres";
    case LinearMethod::kBiCgStab: return "bicgstab";
  }
  return "unknown";
}

const char* preconditionerName(PreconditionerKind kind) {
  switch (kind) {
    case PreconditionerKind::kJacobi: return "jacobi";
    case PreconditionerKind::kCholesky: return "cholesky";
    case PreconditionerKind::kAmg: return "amg";
  }
  return "unknown";
}

bool operator==(const LinearSolveSettings& a, const LinearSolveSettings& b) {
  const AmgSettings &p = a.amg, &q = b.amg;
  return a.method == b.method && a.gmresRestart == b.gmresRestart &&
         a.tolerance == b.tolerance && a.maxIterations == b.maxIterations &&
         a.preconditioner == b.preconditioner && a.refactorIterations == b.refactorIterations &&
         a.backgroundRefactor == b.backgroundRefactor && a.choleskyBackend == b.choleskyBackend &&
         p.strongThreshold == q.strongThreshold && p.numFunctions == q.numFunctions &&
         p.coarsenType == q.coarsenType && p.interpMaxElements == q.interpMaxElements &&
         p.aggressiveLevels == q.aggressiveLevels && p.relaxType == q.relaxType &&
         p.maxLevels == q.maxLevels;
}

LinearSolve::LinearSolve(LinearSolveSettings settings, LinearSolveRule rule)
    : settings_(settings), rule_(rule) {}

void LinearSolve::configure(const LinearSolveSettings& settings) {
  if (settings == settings_) return;
  settings_ = settings;
  factor_.reset();
  factorRows_ = -1;
  projecting_ = false;
}

void LinearSolve::makeFactorHolder() {
  if (factor_) return;
  if (settings_.preconditioner == PreconditionerKind::kAmg)
    factor_ = std::make_unique<AmgPreconditioner>(settings_.amg);
  else
    factor_ = std::make_unique<CholeskyPreconditioner>(settings_.backgroundRefactor,
                                                       settings_.choleskyBackend);
  solvesSinceRefusal_ = rule_.retryAfterRefusal;  // the first factor does not wait
}

void LinearSolve::installFinishedFactor() {
  if (factor_) factor_->update();
}

const Preconditioner* LinearSolve::factor(Eigen::Index rows) const {
  if (!factor_ || !factor_->ready() || factorRows_ != rows) return nullptr;
  return factor_.get();
}

const SparseMatrix& LinearSolve::factorMatrix(const SparseMatrix& A, FactorFallbacks* fallbacks) {
  if (!projecting_ || !fallbacks) return A;
  ++diagnostics_.projectedFactors;
  return fallbacks->projectedMatrix();
}

bool LinearSolve::buildNow(const SparseMatrix& A) {
  if (!factor_->rebuildNow(A)) return false;
  factorRows_ = A.rows();
  return true;
}

bool LinearSolve::factorNowOrFallBack(const SparseMatrix& A, FactorFallbacks* fallbacks) {
  if (buildNow(factorMatrix(A, fallbacks))) return true;
  if (!fallbacks) return false;
  // The projected matrix of this state is positive definite and closest to A; without a
  // projection the rest shape's matrix is, and stays close enough to precondition the
  // matrices near it.
  const bool projectable = !projecting_ && fallbacks->canProject();
  if (projectable) {
    projecting_ = true;
    if (buildNow(factorMatrix(A, fallbacks))) return true;
  }
  return buildNow(fallbacks->restMatrix());
}

void LinearSolve::noteBuilds() {
  const bool amg = settings_.preconditioner == PreconditionerKind::kAmg;
  int& refused = amg ? diagnostics_.amgFailures : diagnostics_.notPositiveDefinite;
  if (factor_->refusals() > refused) solvesSinceRefusal_ = 0;
  refused = factor_->refusals();
  diagnostics_.factorizations = factor_->builds();
  if (!factor_->lastRefusal().empty()) diagnostics_.lastRefusal = factor_->lastRefusal();
}

void LinearSolve::ensureFactor(const SparseMatrix& A, FactorFallbacks* fallbacks) {
  if (!usesFactors()) return;
  makeFactorHolder();
  if (factor_->ready() || factor_->busy() || waitingAfterRefusal()) return;
  factorNowOrFallBack(A, fallbacks);
  noteBuilds();
}

const Preconditioner& LinearSolve::jacobiOf(const SparseMatrix& A) {
  diagonal_ = A.diagonal();
  jacobi_.setDiagonal(diagonal_);
  return jacobi_;
}

LinearSolveReport LinearSolve::solve(const SparseMatrix& A, const Eigen::VectorXd& b,
                                     Eigen::VectorXd& x, FactorFallbacks* fallbacks) {
  if (b.lpNorm<Eigen::Infinity>() == 0.0) {
    x.setZero(b.size());
    diagnostics_.lastRelativeResidual = 0.0;
    return {};
  }
  if (rule_.afterSlowSolve == LinearSolveRule::AfterSlowSolve::kSolveAgainWithNewFactor)
    return solveWithGoodFactor(A, b, x, fallbacks);
  return solveKeepingAnswer(A, b, x, fallbacks);
}

LinearSolveReport LinearSolve::solveKeepingAnswer(const SparseMatrix& A,
                                                  const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                                  FactorFallbacks* fallbacks) {
  const Preconditioner* M = &jacobiOf(A);
  if (factor_ && factor_->ready())
    M = factor_.get();
  else if (factor_)
    ++diagnostics_.jacobiFallbacks;
  const LinearSolveReport report = finish(krylov(A, b, x, *M, settings_.maxIterations));
  considerRefactor(A, report, fallbacks);
  return report;
}

LinearSolveReport LinearSolve::solveWithGoodFactor(const SparseMatrix& A,
                                                   const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                                   FactorFallbacks* fallbacks) {
  if (!usesFactors()) return finish(krylov(A, b, x, jacobiOf(A), settings_.maxIterations));
  makeFactorHolder();
  ++solvesSinceRefusal_;
  int keptIterations = 0;
  if (settings_.refactorIterations > 0 && factor(A.rows())) {
    guess_ = x;
    const LinearSolveReport kept = krylov(A, b, x, *factor_, settings_.refactorIterations);
    // b . x > 0 is what a positive definite A gives; a kept factor of another matrix can
    // lead CG past an indefinite one without it noticing.
    if (kept.converged() && b.dot(x) > 0.0) return finish(kept);
    keptIterations = kept.iterations;
    x = guess_;
  }
  LinearSolveReport report;
  if (waitingAfterRefusal() || !factorNowOrFallBack(A, fallbacks)) {
    noteBuilds();
    report.refused = true;
    report.iterations = keptIterations;
    return report;
  }
  noteBuilds();
  report = krylov(A, b, x, *factor_, settings_.maxIterations);
  report.iterations += keptIterations;
  return finish(report);
}

LinearSolveReport LinearSolve::krylov(const SparseMatrix& A, const Eigen::VectorXd& b,
                                      Eigen::VectorXd& x, const Preconditioner& M,
                                      int maxIterations) {
  const SolveSettings settings{settings_.tolerance, maxIterations, settings_.gmresRestart};
  const MatrixOperator op(A);
  const auto reported = [](const SolveReport& solved) {
    LinearSolveReport r;
    r.iterations = solved.iterations;
    r.relativeResidual = solved.relativeResidual;
    r.outcome = solved.outcome;
    r.lostCurvature = solved.outcome == SolveOutcome::kNonPositiveCurvature;
    return r;
  };
  switch (settings_.method) {
    case LinearMethod::kGmres: return reported(gmres(op, b, x, M, settings, workspace_));
    case LinearMethod::kBiCgStab: return reported(biCgStab(op, b, x, M, settings, workspace_));
    case LinearMethod::kPcg: break;
  }
  // CG needs a positive definite A (and preconditioner): a non-positive Jacobi diagonal says
  // A is not.
  const bool cgApplies = &M != &jacobi_ || jacobi_.positive();
  LinearSolveReport report;
  if (rule_.biCgStabOnLostCurvature) guess_ = x;
  if (cgApplies) {
    report = reported(conjugateGradients(op, b, x, M, settings, workspace_));
    if (!report.lostCurvature) return report;
  }
  ++diagnostics_.nonPositiveCurvature;
  report.lostCurvature = true;
  report.outcome = SolveOutcome::kNonPositiveCurvature;
  if (!rule_.biCgStabOnLostCurvature) return report;
  const int cgIterations = report.iterations;
  x = guess_;
  report = reported(biCgStab(op, b, x, M, settings, workspace_));
  report.iterations += cgIterations;
  report.lostCurvature = true;
  return report;
}

void LinearSolve::considerRefactor(const SparseMatrix& A, const LinearSolveReport& report,
                                   FactorFallbacks* fallbacks) {
  if (!factor_) return;
  ++solvesSinceRefusal_;
  // Negative curvature says the factor is stale, unless it is a projected one: the exact
  // matrix is indefinite then, and a new factor would meet it again.
  const bool slow = report.iterations > settings_.refactorIterations ||
                    (report.lostCurvature && !projecting_);
  if (slow && !factor_->busy() && !waitingAfterRefusal()) {
    const SparseMatrix& M = factorMatrix(A, fallbacks);
    if (factor_->rebuild(M)) factorRows_ = M.rows();
  }
  noteBuilds();
}

LinearSolveReport LinearSolve::finish(LinearSolveReport report) {
  if (!report.converged()) ++diagnostics_.unconvergedLinear;
  diagnostics_.lastRelativeResidual = report.relativeResidual;
  diagnostics_.lastIterations = report.iterations;
  return report;
}

}  // namespace tt
