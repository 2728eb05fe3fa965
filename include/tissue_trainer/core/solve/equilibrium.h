#pragma once
// Quasistatic equilibrium: the positions of the free DOFs at which the total force vanishes,
// f(x) = 0, at the current loads and with the constrained DOFs where the caller put them (M.
// Bao, "Derivation of Quasistatics and Landmark Optimization for Muscles", Secs. 2-3, Eq. 3,
// solved by Newton-Raphson as in Sec. 5.1).
//
// Newton-Raphson on the assembled stiffness: each iteration solves (-K) dx = f over the free
// DOFs (K = df/dx; constrained rows and columns made identity, their right side zero) by
// preconditioned conjugate gradients with the Jacobi preconditioner, or a sparse Cholesky
// factor or BoomerAMG hierarchy kept by the rule of solve/linear_solve.h
// (LinearSolveRule::newtonDirections): kept across Newton iterations and across solves
// (frames), CG on the current -K preconditioned by the factor of an earlier one converges to
// the same linear tolerance, and a new factor is made (and the step solved again with it)
// only when that CG needs more than refactorIterations iterations or does not give a descent
// direction (0: a new factor every Newton iteration). When -K is not positive definite (CG
// meets non-positive curvature, or Jacobi a non-positive diagonal, or the factorisation is
// refused), the solve is repeated on -K + mu I with mu = shiftFraction * mean |diag(-K)|,
// multiplied by 10 until CG succeeds (Levenberg-Marquardt); after maxShifts such tries the
// step is the Jacobi-scaled force, f_i / |(-K)_ii| (a preconditioned gradient step). Whether
// to project the models' element tangents to PSD is the models' own option.
//
// The step is damped by backtracking (halving) on the total potential energy
// Pi(x) = sum of the models' energies - f_ext . x (the energies the force pass returns, so a
// trial costs one force evaluation; Armijo's condition,
// Pi(x + a dx) <= Pi(x) - c a f . dx), or, when a model has no energy, on the residual norm
// (|f(x + a dx)| <= (1 - c a) |f(x)|). Follower loads (ForceModel::isFollowerLoad, e.g. a
// follower pressure) have no energy; when they are the only such models the merit is Pi with
// their force held at its value g_k at the Newton iteration's start, Pi_k(x) = energies -
// (f_ext + g_k) . x, whose slope at x_k is the full residual's, as for a dead load. (On a
// slender beam the full Newton step raises the residual a hundredfold while lowering Pi_k: the
// residual test took steps of 1/1000 and hundreds of iterations per load step.) Near the solution the energy change can fall below
// its round-off (1e-12 of the energy); a step of at least 1/8 of Newton's whose energy change
// is within round-off is then taken when it passes Armijo's test or lowers the residual. A
// shorter one is refused: it lands in the round-off where the energy refused the longer ones,
// and its residual moves by a hair; accepted, Newton crept at one residual for all its
// iterations and the recovery below never started (80 % compression of a muscle block with
// inversion handling, test_equilibrium_stall.cpp).
//
// Where the assembled stiffness is not the force's derivative (at the clamped elements of the
// inversion handling, material/law_point.h, or with PSD-projected tangents) Newton converges
// only linearly: in 80 % compression of a muscle block about 0.7 per iteration, more than the
// 50 iterations of a frame. After kSlowIterations full steps in a row that each left more than
// kLinearRate of the residual, the solve takes Jacobian-free Newton-Krylov steps (D. A. Knoll
// and D. E. Keyes, "Jacobian-free Newton-Krylov methods: a survey of approaches and
// applications", J. Comput. Phys. 193, 2004): GMRES on the force's own derivative, its
// products -df/dx v by a forward difference of the force (one force pass each), started from
// the stiffness's step and preconditioned by the stiffness's factor (or its diagonal), their
// line search on the residual norm (a Newton step on the force's derivative descends |f|^2,
// not the energy, from which the force at a clamped element does not derive). Kept while each
// lowers the residual by more than kLinearRate; a refused one falls back to the stiffness's
// step. The same step is tried where the energy's line search refuses both the stiffness's
// step and the scaled force, before the pseudo-time recovery below.
//
// When no step length is accepted (with the threshold-clamped inversion handling of
// material/law_point.h the force at a clamped element is not the energy's gradient, and a
// fully inverted body gets stuck here), or when an element is inverted at the start of a
// Newton iteration, the solve goes on with the pseudo-time steps of PseudoTimeRecovery below
// and returns to Newton once no element is inverted and those steps have become Newton's.
//
// Converged when |f_free| <= max(absoluteTolerance, relativeTolerance * |f_free(x0)|)
// (2-norms over the free DOFs, x0 the warm start), or after an unshifted Newton step that moves no
// coordinate by more than 32 units in the last place of the largest one (the residual is then
// the force's round-off, which for stiff tissue can exceed a tolerance in newtons; the report
// says atRoundOff). The velocities play no part (the
// force is evaluated at v = 0) and solveEquilibrium leaves them zero.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "tissue_trainer/core/mesh/corrupt_elements.h"
#include "tissue_trainer/core/solve/krylov.h"
#include "tissue_trainer/core/solve/linear_solve.h"
#include "tissue_trainer/core/system.h"

namespace tt {

struct EquilibriumParams {
  double absoluteTolerance = 1e-9;  // N, on |f| over the free DOFs
  double relativeTolerance = 1e-9;  // of the residual at the warm start
  int maxNewtonIterations = 50;
  double linearTolerance = 1e-10;  // relative residual of each CG solve
  int linearMaxIterations = 2000;
  using Preconditioning = PreconditionerKind;
  Preconditioning preconditioner = Preconditioning::kJacobi;
  int maxLineSearchSteps = 30;  // halvings of a Newton step
  double armijo = 1e-4;         // c of the sufficient-decrease condition
  // Cholesky, AMG: CG iterations above which the kept factor is replaced by one of the
  // current matrix (0: a new factor every Newton iteration).
  int refactorIterations = 20;
  double shiftFraction = 1e-3;  // first mu of the shifted solve, of mean |diag(-K)|
  int maxShifts = 8;            // shifted tries before the gradient step
  // Pseudo-time steps per solve where elements are inverted or the line search fails (0:
  // none; Newton goes on from inverted states and fails where the line search does).
  int maxPseudoTimeSteps = 200;
  // Mass term of the first pseudo-time step, of the mean stiffness diagonal (PseudoTimeRecovery).
  double pseudoTimeInitialRatio = 1e-3;

  // The settings of the Newton steps' linear solve (PCG, factors made synchronously).
  LinearSolveSettings linearSolve() const;
  // Takes tolerance, iterations, preconditioner and refactorIterations of s.
  void setLinearSolve(const LinearSolveSettings& s);
};

enum class EquilibriumStop {
  kConverged,
  kIterationLimit,      // maxNewtonIterations reached above the tolerance
  kLineSearchFailed,    // no step length decreased the energy (or the residual), and the
                        // pseudo-time recovery did not get out either
  kNonFiniteForce,      // a non-finite force or stiffness at an accepted state
  kNoStiffness,         // a model provides no analytic stiffness
  kRecoveryFailed,      // maxPseudoTimeSteps taken with elements still inverted
};

const char* stopName(EquilibriumStop stop);

// -K at x (K = df/dx) with the constrained rows and columns made identity, and the offsets of
// its diagonal entries in A's values (found when the size changes); false when K is not finite.
bool assembleConstrainedNegativeStiffness(const System& system, const Eigen::VectorXd& x,
                                          SparseMatrix& A, std::vector<int>& diagonalOffsets);

struct EquilibriumReport {
  int newtonIterations = 0;  // Newton steps taken
  int linearIterations = 0;  // CG iterations over all solves (shifted ones included)
  int shiftedSolves = 0;     // Newton steps whose matrix needed a shift
  int gradientSteps = 0;     // Newton steps that fell back to the scaled force
  int derivativeSteps = 0;   // Newton steps on the force's own derivative (Jacobian-free)
  int forceEvaluations = 0;  // force passes: the start and every line-search trial
  int factorizations = 0;    // Cholesky factorisations made
  int recoveries = 0;        // times Newton handed over to the pseudo-time steps
  int pseudoTimeSteps = 0;   // accepted pseudo-time steps (in residualHistory too)
  int rejectedPseudoTimeSteps = 0;  // tried and redone with a shorter pseudo-time step
  double initialResidual = 0.0;  // |f_free| at the warm start (N)
  double residual = 0.0;         // |f_free| at the end (N)
  std::vector<double> residualHistory;  // |f_free| at the start and after every step
  // Converged with the residual above the tolerance: the Newton step had fallen to the
  // round-off of the positions (EquilibriumSolver::newtonStepBelowRoundOff).
  bool atRoundOff = false;
  EquilibriumStop stop = EquilibriumStop::kConverged;
  std::string reason;  // "" when converged, else a sentence
  bool converged() const { return stop == EquilibriumStop::kConverged; }
};

// Pseudo-transient continuation (C. T. Kelley and D. E. Keyes, "Convergence analysis of
// pseudo-transient continuation", SIAM J. Numer. Anal. 35, 1998; the step length by the
// "switched evolution relaxation" analysed there) for the states Newton cannot leave: damped
// implicit steps
//   (M / tau - K) dx = f(x),   x <- x + dx,
// with M the lumped masses of the free DOFs (the mean free mass where a DOF has none): a
// backward Euler step of length h = sqrt(tau) from rest whose velocity is all damped away,
// what brings an inverted body back under backward Euler. The first tau makes the mass term a
// small part of the stiffness, mean M / tau = params.pseudoTimeInitialRatio mean |diag(-K)|:
// a Newton step kept definite where K is nearly singular, and taken whatever the energy does
// (at a clamped element of material/law_point.h the force is not the energy's gradient) as
// long as the force stays finite, CG meets no non-positive curvature and the residual does
// not grow more than kRejectGrowth-fold; otherwise the step is redone with tau / 4 (counted in
// rejectedPseudoTimeSteps). Each accepted step multiplies tau by |f_before| / |f_after|, by
// kGrowth at most and 1 / kGrowth at least. Back to Newton once
// mean M / tau <= kHandOff mean |diag(-K)| (the steps have become Newton's) and no element is
// inverted; elements still inverted after kSettleSteps such steps belong to the equilibrium of
// an inversion-handled law (80 % compression of a muscle block keeps about two dozen): Newton
// takes over with them, and the recovery is wanted again only for more.
//
// Why near Newton: started with a large mass term (short steps, close to the overdamped flow)
// a fully inverted muscle block settles in another, folded equilibrium of higher energy;
// started with a ratio from 1e-8 to 1e-2 it returns to its rest shape (docs/solvers.md,
// "Inverted elements").
class PseudoTimeRecovery {
 public:
  static constexpr double kGrowth = 10.0;
  static constexpr double kRejectGrowth = 100.0;
  static constexpr double kHandOff = 1e-6;
  // Newton-sized steps after which elements still inverted count as part of the equilibrium
  // (the fully inverted muscle block of test_muscle_inversion.cpp needs 18 steps in all).
  static constexpr int kSettleSteps = 20;

  // At the start of a solve.
  void start();
  // Whether the recovery should take over at x: steps left in params.maxPseudoTimeSteps
  // (over the whole solve, rejected steps included) and an element inverted or flat
  // (mesh/corrupt_elements.h, volume <= 0), more of them than at the last hand-off.
  bool wanted(const System& system, const EquilibriumParams& params, const Eigen::VectorXd& x,
              const EquilibriumReport& report);
  // From x (f the free residual there, residual = |f|) until the hand-off or residual <=
  // target; x, f and residual follow the accepted steps, which the report counts and adds to
  // its residualHistory. False when the steps ran out first (or none were left) or a
  // stiffness was not finite.
  bool run(const System& system, const EquilibriumParams& params, double target,
           Eigen::VectorXd& x, Eigen::VectorXd& f, double& residual, EquilibriumReport& report);

 private:
  bool stepsLeft(const EquilibriumParams& params, const EquilibriumReport& report) const;
  int invertedElements(const System& system, const Eigen::VectorXd& x);
  // -K at x with the constraints applied, and the mean |diagonal| over the free DOFs; false
  // when not finite.
  bool assemble(const System& system, const Eigen::VectorXd& x, double& meanDiagonal);
  // dx_ from (M / tau - K) dx = f with a new factor of that matrix where the preconditioner
  // is one; false on non-positive curvature or a refused factorisation.
  bool solveStep(const System& system, const EquilibriumParams& params, double tau,
                 const Eigen::VectorXd& f, EquilibriumReport& report);
  // One step of length tau from x: taken (x, f, residual moved, tau grown or shrunk by the
  // residual's ratio) or refused (nothing changed).
  bool tryStep(const System& system, const EquilibriumParams& params, double& tau,
               Eigen::VectorXd& x, Eigen::VectorXd& f, double& residual,
               EquilibriumReport& report);

  SparseMatrix A_;
  std::vector<int> diagonal_;  // offsets of the diagonal entries in A_'s values
  Eigen::VectorXd weight_, stiffnessDiagonal_, shiftedDiagonal_, dx_, trial_, trialF_,
      zeroVelocity_;
  LinearSolve linear_{{}, LinearSolveRule::newtonDirections()};
  CorruptElementCheck corruptCheck_;
  int settledInverted_ = 0;  // elements inverted at the last hand-off of this solve
  const Mesh* checkedMesh_ = nullptr;  // the mesh corruptCheck_ was built for
  int checkedElements_ = 0;            // and its number of tets and hexes then
};

// Keeps the matrices, vectors and preconditioners between solves (no allocation once sized).
class EquilibriumSolver {
 public:
  static constexpr double kLinearRate = 0.5;  // residual ratio of a linearly converging step
  static constexpr int kSlowIterations = 2;   // such full steps in a row before switching
  static constexpr int kDerivativeIterations = 40;  // GMRES products per Jacobian-free step
  static constexpr double kDerivativeTolerance = 1e-6;  // GMRES, relative to |f|
  static constexpr double kDerivativeForcing = 1e-2;    // the most GMRES may leave of |f|

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
  bool newtonStepBelowRoundOff(const Eigen::VectorXd& x) const;
  // The energy at x after pseudo-time steps moved it (f_ refreshed too).
  double potentialAfterRecovery(const System& system, const Eigen::VectorXd& x,
                                EquilibriumReport& report);
  // The Newton direction dx_ from -K dx = f_ at x (shifted, or the scaled force, where -K is
  // not positive definite); false when the stiffness is not finite.
  bool newtonDirection(const System& system, const Eigen::VectorXd& x, EquilibriumReport& report);
  void scaledForceDirection();  // dx_ = f_ / |diag(A_)| (free DOFs)
  // CG on A_ with its diagonal shift and preconditioner M (the shifted solves); false on
  // non-positive curvature.
  bool conjugateGradientSolve(const Preconditioner& M, EquilibriumReport& report);
  // dx_ by the linear solve (Jacobi, or a kept or new factor); false where -K is not positive
  // definite (non-positive curvature, or a refused factorisation).
  bool unshiftedDirection(EquilibriumReport& report);
  // What the line search judges a step by: the total potential energy where every model has
  // one (else the residual), or the residual norm alone.
  enum class Merit { kEnergy, kResidual };
  // Backtracking along dx_ from x; false when no length was accepted. lastStep_ gets the
  // accepted length.
  bool lineSearch(const System& system, Eigen::VectorXd& x, double& residual,
                  EquilibriumReport& report, Merit merit = Merit::kEnergy);
  // dx_ from GMRES on -df/dx dx = f_ (forward-difference products), started from the
  // stiffness's step in stiffnessDx_; false when GMRES left more than kDerivativeForcing.
  bool forceDerivativeDirection(const System& system, const Eigen::VectorXd& x,
                                EquilibriumReport& report);
  // A line search on the residual along that step; whether x moved.
  bool derivativeStep(const System& system, Eigen::VectorXd& x, double& residual,
                      EquilibriumReport& report);
  // From the stiffness's step in dx_: the force's derivative step while onDerivative_, else
  // (or where it is refused) the stiffness's step or the scaled force by the energy, and the
  // derivative step where the energy refuses both. Whether x moved.
  bool takeStep(const System& system, Eigen::VectorXd& x, double& residual,
                EquilibriumReport& report);

  SparseMatrix A_;
  std::vector<int> diagonal_;  // offsets of the diagonal entries in A_'s values
  Eigen::VectorXd f_, trialF_, dx_, trial_, diagonalValues_, zeroVelocity_;
  LinearSolve linear_{{}, LinearSolveRule::newtonDirections()};
  JacobiPreconditioner shiftedJacobi_;  // of the shifted solves
  double potential_ = 0.0;          // at the current x (with f_)
  double lastStep_ = 0.0;           // the length the last line search accepted
  int slowIterations_ = 0;          // full steps in a row that left > kLinearRate
  bool onDerivative_ = false;       // Jacobian-free steps while they beat kLinearRate
  Eigen::VectorXd stiffnessDx_, differenceX_, differenceF_;
  JacobiPreconditioner derivativeJacobi_;
  KrylovWorkspace krylov_;
  bool hasEnergy_ = true;
  // With follower loads: their force at the current Newton iteration's start (the merit's
  // dead load); empty without.
  bool holdsFollowerLoads_ = false;
  Eigen::VectorXd heldLoad_, followerScratch_;
  // Refreshes heldLoad_ to the follower loads' force at x and potential_ with it.
  void holdFollowerLoads(const System& system, const Eigen::VectorXd& x);
  PseudoTimeRecovery recovery_;
};

// The free DOFs of system.state.x moved to equilibrium at the current loads and constrained
// positions (warm start: the current state); the velocities set to zero.
EquilibriumReport solveEquilibrium(System& system, const EquilibriumParams& params = {});
// The same with a report parameter, as the integrators fill theirs.
void solveEquilibrium(System& system, const EquilibriumParams& params, EquilibriumReport& report);

}  // namespace tt
