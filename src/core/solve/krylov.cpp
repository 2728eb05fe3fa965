#include "tissue_trainer/core/solve/krylov.h"

#include <cmath>

namespace tt {

const char* outcomeName(SolveOutcome outcome) {
  switch (outcome) {
    case SolveOutcome::kConverged: return "converged";
    case SolveOutcome::kMaxIterations: return "iteration limit";
    case SolveOutcome::kNonPositiveCurvature: return "non-positive curvature";
    case SolveOutcome::kBreakdown: return "breakdown";
  }
  return "?";
}

bool JacobiPreconditioner::setDiagonal(const Eigen::VectorXd& diagonal) {
  inverse_.resize(diagonal.size());
  bool usable = true;
  positive_ = true;
  for (Eigen::Index i = 0; i < diagonal.size(); ++i) {
    const double d = diagonal[i];
    positive_ = positive_ && d > 0.0;
    const bool ok = std::isfinite(d) && d != 0.0;
    usable = usable && ok;
    inverse_[i] = ok ? 1.0 / d : 1.0;
  }
  positive_ = positive_ && usable;
  return usable;
}

bool JacobiPreconditioner::setFromMatrix(const SparseMatrix& A) {
  return setDiagonal(A.diagonal());
}

namespace {

// The residual r = b - A x and whether it already meets the tolerance.
bool startResidual(const LinearOperator& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                   double threshold, double bNorm, KrylovWorkspace& w, SolveReport& report) {
  A.apply(x, w.q);
  w.r = b - w.q;
  const double rNorm = w.r.norm();
  report.relativeResidual = rNorm / bNorm;
  return rNorm <= threshold;
}

// A zero right side: x = 0 solves it exactly.
bool zeroRightSide(const Eigen::VectorXd& b, Eigen::VectorXd& x, SolveReport& report) {
  if (b.squaredNorm() != 0.0) return false;
  x.setZero(b.size());
  report.relativeResidual = 0.0;
  return true;
}

}  // namespace

SolveReport conjugateGradients(const LinearOperator& A, const Eigen::VectorXd& b,
                               Eigen::VectorXd& x, const Preconditioner& M,
                               const SolveSettings& settings, KrylovWorkspace& w) {
  SolveReport report;
  if (zeroRightSide(b, x, report)) return report;
  const double bNorm = b.norm(), threshold = settings.tolerance * bNorm;
  if (startResidual(A, b, x, threshold, bNorm, w, report)) return report;
  M.apply(w.r, w.z);
  w.p = w.z;
  double rz = w.r.dot(w.z);
  while (report.iterations < settings.maxIterations) {
    A.apply(w.p, w.q);
    ++report.iterations;
    const double curvature = w.p.dot(w.q);
    if (!(curvature > 0.0)) {
      report.outcome = SolveOutcome::kNonPositiveCurvature;
      return report;
    }
    const double alpha = rz / curvature;
    x += alpha * w.p;
    w.r -= alpha * w.q;
    const double rNorm = w.r.norm();
    report.relativeResidual = rNorm / bNorm;
    if (rNorm <= threshold) return report;
    M.apply(w.r, w.z);
    const double rzNext = w.r.dot(w.z);
    w.p = w.z + (rzNext / rz) * w.p;
    rz = rzNext;
  }
  report.outcome = SolveOutcome::kMaxIterations;
  return report;
}

// Van der Vorst's BiCGSTAB, right-preconditioned (x is updated with M^-1 p and M^-1 s).
SolveReport biCgStab(const LinearOperator& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                     const Preconditioner& M, const SolveSettings& settings,
                     KrylovWorkspace& w) {
  SolveReport report;
  if (zeroRightSide(b, x, report)) return report;
  const double bNorm = b.norm(), threshold = settings.tolerance * bNorm;
  if (startResidual(A, b, x, threshold, bNorm, w, report)) return report;
  w.shadow = w.r;
  w.p.setZero(b.size());
  w.v.setZero(b.size());
  double rho = 1.0, alpha = 1.0, omega = 1.0;
  while (report.iterations < settings.maxIterations) {
    const double rhoNext = w.shadow.dot(w.r);
    if (rhoNext == 0.0 || omega == 0.0) break;
    w.p = w.r + (rhoNext / rho) * (alpha / omega) * (w.p - omega * w.v);
    rho = rhoNext;
    M.apply(w.p, w.y);
    A.apply(w.y, w.v);
    ++report.iterations;
    const double denominator = w.shadow.dot(w.v);
    if (denominator == 0.0) break;
    alpha = rho / denominator;
    w.s = w.r - alpha * w.v;
    if (w.s.norm() <= threshold) {
      x += alpha * w.y;
      report.relativeResidual = w.s.norm() / bNorm;
      return report;
    }
    M.apply(w.s, w.z);
    A.apply(w.z, w.t);
    ++report.iterations;
    const double tt = w.t.squaredNorm();
    if (tt == 0.0) {
      x += alpha * w.y;
      break;
    }
    omega = w.t.dot(w.s) / tt;
    x += alpha * w.y + omega * w.z;
    w.r = w.s - omega * w.t;
    report.relativeResidual = w.r.norm() / bNorm;
    if (report.relativeResidual <= settings.tolerance) return report;
  }
  report.outcome = report.iterations >= settings.maxIterations ? SolveOutcome::kMaxIterations
                                                               : SolveOutcome::kBreakdown;
  return report;
}

// Restarted GMRES(m) with modified Gram-Schmidt and Givens rotations (Saad, "Iterative
// methods for sparse linear systems", 2nd ed., Secs. 6.5 and 9.3.2: right-preconditioned).
SolveReport gmres(const LinearOperator& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                  const Preconditioner& M, const SolveSettings& settings, KrylovWorkspace& w) {
  SolveReport report;
  if (zeroRightSide(b, x, report)) return report;
  const int m = std::max(1, settings.restart);
  const double bNorm = b.norm(), threshold = settings.tolerance * bNorm;
  w.basis.resize(m + 1);
  w.hessenberg.setZero(m + 1, m);
  w.cosines.setZero(m);
  w.sines.setZero(m);
  w.g.setZero(m + 1);
  while (report.iterations < settings.maxIterations) {
    if (startResidual(A, b, x, threshold, bNorm, w, report)) return report;
    const double beta = w.r.norm();
    w.basis[0] = w.r / beta;
    w.g.setZero();
    w.g[0] = beta;
    w.hessenberg.setZero();
    int k = 0;
    bool lucky = false;
    while (k < m && report.iterations < settings.maxIterations) {
      M.apply(w.basis[k], w.z);
      A.apply(w.z, w.t);
      ++report.iterations;
      for (int i = 0; i <= k; ++i) {
        w.hessenberg(i, k) = w.t.dot(w.basis[i]);
        w.t -= w.hessenberg(i, k) * w.basis[i];
      }
      const double next = w.t.norm();
      w.hessenberg(k + 1, k) = next;
      for (int i = 0; i < k; ++i) {  // earlier rotations on the new column
        const double a = w.hessenberg(i, k), c = w.hessenberg(i + 1, k);
        w.hessenberg(i, k) = w.cosines[i] * a + w.sines[i] * c;
        w.hessenberg(i + 1, k) = -w.sines[i] * a + w.cosines[i] * c;
      }
      const double d = std::hypot(w.hessenberg(k, k), w.hessenberg(k + 1, k));
      if (d == 0.0) {
        report.outcome = SolveOutcome::kBreakdown;
        break;
      }
      w.cosines[k] = w.hessenberg(k, k) / d;
      w.sines[k] = w.hessenberg(k + 1, k) / d;
      w.hessenberg(k, k) = d;
      w.hessenberg(k + 1, k) = 0.0;
      w.g[k + 1] = -w.sines[k] * w.g[k];
      w.g[k] *= w.cosines[k];
      ++k;
      report.relativeResidual = std::abs(w.g[k]) / bNorm;
      if (std::abs(w.g[k]) <= threshold) break;
      if (next == 0.0) {  // the Krylov space holds the solution
        lucky = true;
        break;
      }
      w.basis[k] = w.t / next;
    }
    if (k > 0) {
      const Eigen::VectorXd y = w.hessenberg.topLeftCorner(k, k)
                                    .triangularView<Eigen::Upper>()
                                    .solve(w.g.head(k));
      w.v.setZero(b.size());
      for (int i = 0; i < k; ++i) w.v += y[i] * w.basis[i];
      M.apply(w.v, w.z);
      x += w.z;
    }
    if (report.outcome == SolveOutcome::kBreakdown) return report;
    if (report.relativeResidual <= settings.tolerance || lucky) {
      report.outcome = SolveOutcome::kConverged;
      return report;
    }
  }
  report.outcome = SolveOutcome::kMaxIterations;
  return report;
}

}  // namespace tt
