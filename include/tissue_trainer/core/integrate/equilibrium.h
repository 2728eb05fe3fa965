#pragma once
// Quasistatic equilibrium: the positions of the free DOFs at which the total force vanishes,
// f(x) = 0, at the current loads and with the constrained DOFs where the caller put them (M.
// Bao, "Derivation of Quasistatics and Landmark Optimization for Muscles", Secs. 2-3, Eq. 3,
// solved by Newton-Raphson as in Sec. 5.1).
//
// Newton-Raphson on the assembled stiffness: each iteration solves (-K) dx = f over the free
// DOFs (K = df/dx; constrained rows and columns made identity, their right side zero) by
// preconditioned conjugate gradients (solve/krylov.h) with the Jacobi or the sparse Cholesky
// preconditioner of the implicit integrators. The Cholesky factor is kept across Newton
// iterations and across solves (frames): CG on the current -K, preconditioned by the factor of
// an earlier one, converges to the same linear tolerance, and a new factor is made only when
// that CG needs more than refactorAbove iterations or does not give a descent direction (0:
// a new factor every Newton iteration). When -K is not positive definite (CG meets
// non-positive curvature, or Jacobi a non-positive diagonal, or the Cholesky factorisation is
// refused), the solve is repeated on -K + mu I with mu = shiftFraction * mean |diag(-K)|,
// multiplied by 10 until CG succeeds (Levenberg-Marquardt); after maxShifts such tries the
// step is the Jacobi-scaled force, f_i / |(-K)_ii| (a preconditioned gradient step). Whether
// to project the models' element tangents to PSD is the models' own option.
//
// The step is damped by backtracking (halving) on the total potential energy
// Pi(x) = sum of the models' energies - f_ext . x (the energies the force pass returns, so a
// trial costs one force evaluation; Armijo's condition,
// Pi(x + a dx) <= Pi(x) - c a f . dx), or, when a model has no energy, on the residual norm
// (|f(x + a dx)| <= (1 - c a) |f(x)|). Near the solution the energy change can fall below
// its round-off; a step whose energy change is within round-off and whose residual is smaller
// is then taken as well.
//
// Converged when |f_free| <= max(absoluteTolerance, relativeTolerance * |f_free(x0)|)
// (2-norms over the free DOFs, x0 the warm start). The velocities play no part (the
// force is evaluated at v = 0) and solveEquilibrium leaves them zero.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "tissue_trainer/core/solve/cholesky_preconditioner.h"
#include "tissue_trainer/core/solve/krylov.h"
#include "tissue_trainer/core/system.h"

namespace tt {

struct EquilibriumParams {
  double absoluteTolerance = 1e-9;  // N, on |f| over the free DOFs
  double relativeTolerance = 1e-9;  // of the residual at the warm start
  int maxNewtonIterations = 50;
  double linearTolerance = 1e-10;  // relative residual of each CG solve
  int linearMaxIterations = 2000;
  enum class Preconditioning { kJacobi, kCholesky };
  Preconditioning preconditioner = Preconditioning::kJacobi;
  int maxLineSearchSteps = 30;  // halvings of a Newton step
  double armijo = 1e-4;         // c of the sufficient-decrease condition
  // Cholesky: CG iterations above which the kept factor is replaced by one of the current
  // matrix (0: a new factor every Newton iteration).
  int refactorAbove = 20;
  double shiftFraction = 1e-3;  // first mu of the shifted solve, of mean |diag(-K)|
  int maxShifts = 8;            // shifted tries before the gradient step
};

enum class EquilibriumStop {
  kConverged,
  kIterationLimit,      // maxNewtonIterations reached above the tolerance
  kLineSearchFailed,    // no step length decreased the energy (or the residual)
  kNonFiniteForce,      // a non-finite force or stiffness at an accepted state
  kNoStiffness,         // a model provides no analytic stiffness
};

const char* stopName(EquilibriumStop stop);

struct EquilibriumReport {
  int newtonIterations = 0;  // Newton steps taken
  int linearIterations = 0;  // CG iterations over all solves (shifted ones included)
  int shiftedSolves = 0;     // Newton steps whose matrix needed a shift
  int gradientSteps = 0;     // Newton steps that fell back to the scaled force
  int forceEvaluations = 0;  // force passes: the start and every line-search trial
  int factorizations = 0;    // Cholesky factorisations made
  double initialResidual = 0.0;  // |f_free| at the warm start (N)
  double residual = 0.0;         // |f_free| at the end (N)
  std::vector<double> residualHistory;  // |f_free| at the start and after every step
  EquilibriumStop stop = EquilibriumStop::kConverged;
  std::string reason;  // "" when converged, else a sentence
  bool converged() const { return stop == EquilibriumStop::kConverged; }
};

// Keeps the matrices, vectors and preconditioners between solves (no allocation once sized).
class EquilibriumSolver {
 public:
  explicit EquilibriumSolver(EquilibriumParams params = {});
  // Moves the free DOFs of x (3n; warm start) to equilibrium; the constrained DOFs of x stay
  // as given. The system's state is not touched.
  EquilibriumReport solve(const System& system, Eigen::VectorXd& x);

  EquilibriumParams params;

 private:
  // Free residual f (constrained entries zero) at x; its 2-norm. `potential` gets the total
  // potential energy there (NaN when a model has none).
  double residualAt(const System& system, const Eigen::VectorXd& x, Eigen::VectorXd& f,
                    double& potential, EquilibriumReport& report) const;
  // The Newton direction dx_ from -K dx = f_ at x (shifted, or the scaled force, where -K is
  // not positive definite); false when the stiffness is not finite.
  bool newtonDirection(const System& system, const Eigen::VectorXd& x, EquilibriumReport& report);
  void scaledForceDirection();  // dx_ = f_ / |diag(A_)| (free DOFs)
  // CG on A_ (with the current diagonal shift), at most maxIterations; false on non-positive
  // curvature, or when it stops unconverged and `mustConverge`.
  bool conjugateGradientSolve(const Preconditioner& M, EquilibriumReport& report,
                              int maxIterations, bool mustConverge = false);
  // dx_ by CG preconditioned with the kept Cholesky factor (within refactorAbove iterations, a
  // descent direction) or else with a new one; false when -K cannot be factored.
  bool choleskyDirection(EquilibriumReport& report);
  // Backtracking along dx_ from x; false when no length was accepted.
  bool lineSearch(const System& system, Eigen::VectorXd& x, double& residual,
                  EquilibriumReport& report);

  SparseMatrix A_;
  std::vector<int> diagonal_;  // offsets of the diagonal entries in A_'s values
  Eigen::VectorXd f_, trialF_, dx_, trial_, diagonalValues_, zeroVelocity_;
  JacobiPreconditioner jacobi_;
  std::unique_ptr<CholeskyPreconditioner> cholesky_;
  Eigen::Index factoredRows_ = -1;  // of the kept factor's matrix
  double potential_ = 0.0;          // at the current x (with f_)
  KrylovWorkspace krylov_;
  bool hasEnergy_ = true;
};

// The free DOFs of system.state.x moved to equilibrium at the current loads and constrained
// positions (warm start: the current state); the velocities set to zero.
EquilibriumReport solveEquilibrium(System& system, const EquilibriumParams& params = {});
// The same with a report parameter, as the integrators fill theirs.
void solveEquilibrium(System& system, const EquilibriumParams& params, EquilibriumReport& report);

}  // namespace tt
