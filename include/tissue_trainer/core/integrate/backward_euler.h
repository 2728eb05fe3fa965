#pragma once
// Linearised implicit (backward) Euler, "Adamss: Advanced Anisotropic Mass-Spring System",
// Sec. 2.5.5, Eqs. 2.142-2.148: one Newton step per time step on v+ = v + h M^-1 f(x+, v+),
// x+ = x + h v+, with f linearised at (x, v):
//   (M - h D - h^2 K) dv = h (f + h K v),   D = df/dv,   K = df/dx
// (the chapter's A and b multiplied by M; its dF/dt term is neglected as in the chapter, and
// the external force is taken at the start of the step). K and D come from the models'
// analytic stiffness and velocity Jacobians (D = -diag(c) plus the models' df/dv), or, with
// jacobian = kFiniteDifference, from forward differences of the total force
// (finite_difference_jacobian.h, Eq. 2.149 with its sign corrected), which needs nothing of
// the models but their forces. Constrained DOFs move to their prescribed position at t + h
// exactly; the coupling of that motion into the free DOFs goes through K.
//
// With newtonIterations > 1 the first step is followed by Newton corrections on the exact
// implicit equations, R(dv) = M dv - h f(x + h (v + dv), v + dv) = 0 (free DOFs), with K
// re-assembled at each iterate, until |R| <= newtonTolerance * |h (f + h K v)|. For a linear
// force the first step already solves these equations, so both variants coincide.
//
// Linear solver (linearSolver): preconditioned conjugate gradients (kPcg), restarted GMRES(m)
// (kGmres) or BiCGSTAB (kBiCgStab), warm-started from the previous dv (scaled by the ratio of
// the step lengths when the step changed). M - h D - h^2 K is symmetric when the models are
// conservative but only positive definite when -K is positive semi-definite "enough"; when CG
// meets non-positive curvature (or a non-positive diagonal), the solve is redone with
// BiCGSTAB and the same preconditioner from the same initial guess, and the event is counted
// in diagnostics(). GMRES and BiCGSTAB take any non-singular matrix (a finite-difference or
// non-conservative one is not symmetric).
//
// Step length: equal substeps per frame, or (adaptive) the iteration-count control of
// Sec. 2.5.5 through HalvingDoublingControl: a step whose Krylov iterations (all its solves)
// reach upperIterations is halved and redone, a step that needs lowerIterations or fewer
// doubles the next one, within [minStep, maxStep]; a step at minStep is kept whatever it
// needed (the count says the solve is costly, not that the step is wrong).
//
// Preconditioners: Jacobi, or the sparse Cholesky factor of an earlier system matrix
// (solve/cholesky_preconditioner.h). The first step factors its own matrix (or, when that is
// not positive definite, the matrix of the rest shape, which is); a solve that
// needs more than refactorIterations iterations, or meets non-positive curvature, starts a
// new factorisation of its matrix (on a thread of its own when backgroundRefactor), which
// takes over at the start of a later step. A matrix that is not positive definite keeps the
// old factor in use (Jacobi while there is none), and the next attempt waits
// kRefactorRetrySolves solves.
//
// Or an algebraic multigrid hierarchy (solve/amg_preconditioner.h, hypre's BoomerAMG) of an
// earlier system matrix, one V-cycle per iteration, kept and rebuilt by the same rules; its
// set-up always runs synchronously, right after the slow solve (backgroundRefactor does not
// apply), and it does not refuse an indefinite matrix (CG meets the non-positive curvature
// instead, and the solve is redone with BiCGSTAB as above). A hypre error counts as a refusal
// (amgFailures, with hypre's message in lastRefusal) and the solves use Jacobi until a set-up succeeds.
#include <Eigen/Core>
#include <limits>
#include <memory>
#include <string>

#include "tissue_trainer/core/integrate/finite_difference_jacobian.h"
#include "tissue_trainer/core/integrate/step_control.h"
#include "tissue_trainer/core/integrate/stepped_integrator.h"
#include "tissue_trainer/core/solve/amg_preconditioner.h"
#include "tissue_trainer/core/solve/cholesky_preconditioner.h"
#include "tissue_trainer/core/solve/krylov.h"

namespace tt {

// The solver defaults (Cholesky-PCG to 1e-3) are the fastest robust set-up measured on the
// organ-scale scenes; docs/solvers.md, "How the defaults were chosen".
struct BackwardEulerParams {
  int substeps = 1;               // equal substeps per frame (read when constructed)
  double linearTolerance = 1e-3;  // relative residual |b - A dv| / |b|
  int linearMaxIterations = 500;
  int newtonIterations = 1;       // 1: the chapter's linearised step; > 1: full Newton
  double newtonTolerance = 1e-6;  // relative residual of the implicit equations
  bool requireConvergence = false;  // Newton not converged: restore the frame, ok = false
  bool warmStart = true;
  enum class Preconditioning { kJacobi, kCholesky, kAmg };
  Preconditioning preconditioner = Preconditioning::kCholesky;
  int refactorIterations = 15;    // cholesky, amg: a solve that needs more starts a new one
  bool backgroundRefactor = true;  // cholesky: factorise on a thread of its own
  CholeskyBackend choleskyBackend = CholeskyBackend::kCholmod;
  AmgSettings amg;                // amg: BoomerAMG's options
  enum class LinearSolver { kPcg, kGmres, kBiCgStab };
  LinearSolver linearSolver = LinearSolver::kPcg;
  int gmresRestart = 30;          // kGmres: Krylov vectors per cycle
  // Iteration-count step control (read when constructed); substeps does not apply.
  bool adaptive = false;
  int lowerIterations = 10;  // at or below: the next step is twice as long
  int upperIterations = 40;  // at or above: the step is halved and redone (> lowerIterations)
  double initialStep = 1e-3, minStep = 1e-6;  // s
  double maxStep = std::numeric_limits<double>::infinity();  // s
  enum class Jacobian { kAnalytic, kFiniteDifference };
  Jacobian jacobian = Jacobian::kAnalytic;
  FiniteDifferenceSettings finiteDifference;  // kFiniteDifference
};

// The controller of the iteration-count step control for these parameters (adaptive).
HalvingDoublingParams iterationStepControl(const BackwardEulerParams& params);

// Counts over the integrator's life (not per frame).
struct BackwardEulerDiagnostics {
  int nonPositiveCurvature = 0;  // CG solves abandoned for BiCGSTAB
  int unconvergedLinear = 0;     // solves that hit linearMaxIterations
  int unconvergedNewton = 0;     // steps whose Newton loop hit newtonIterations (> 1)
  double lastRelativeResidual = 0.0;  // |b - A dv| / |b| reached by the last linear solve
  int lastIterations = 0;             // of the last linear solve
  int factorizations = 0;             // Cholesky factors installed or AMG hierarchies set up
  int notPositiveDefinite = 0;        // matrices the Cholesky factorisation refused
  int projectedFactors = 0;           // factor builds started from the PSD-projected matrix (after a refusal)
  int amgFailures = 0;                // AMG set-ups and V-cycles that hypre failed
  std::string lastRefusal;            // why the last refused factorisation or set-up was refused
  int jacobiFallbacks = 0;            // solves preconditioned by Jacobi for want of a factor
  long jacobianForceEvaluations = 0;  // force evaluations of finite-difference Jacobians
};

class BackwardEulerIntegrator : public SteppedIntegrator {
 public:
  explicit BackwardEulerIntegrator(BackwardEulerParams params = {});
  // With a step-size controller of the caller's (params.substeps and adaptive do not apply).
  BackwardEulerIntegrator(BackwardEulerParams params, std::unique_ptr<StepSizeController> control);
  const char* name() const override { return "backward_euler"; }
  bool needsStiffness() const override {
    return params.jacobian == BackwardEulerParams::Jacobian::kAnalytic;
  }

  const BackwardEulerDiagnostics& diagnostics() const { return diagnostics_; }

  BackwardEulerParams params;

 private:
  FrameStart beginFrame(System& system, double frameTime) override;
  // One linearised step (and Newton corrections): dv_ for the state at step.end.
  StepAttempt attempt(System& system, const StepContext& step, StepReport& report) override;
  std::string accept(System& system, const StepContext& step) override;
  void abandonFrame(const System&) override { dv_.setZero(); }
  // A = M + h c - h^2 K - h D at (x, v), K assembled into A in place: c the per-DOF damping,
  // D the models' df/dv (damping and friction forces are implicit), in C_. With finite
  // differences, A = M - h^2 df/dx - h df/dv of the total force, c included in df/dv (C_).
  // A has the system's pattern (A_, or the rest shape's restA_). The caller applies the
  // constraints.
  // projected: the models' PSD-projected stiffness (System::assembleStiffness).
  void buildMatrix(const System& system, double h, const Eigen::VectorXd& x,
                   const Eigen::VectorXd& v, SparseMatrix& A, bool projected = false);
  bool finiteDifferences() const {
    return params.jacobian == BackwardEulerParams::Jacobian::kFiniteDifference;
  }
  // A = -h^2 df/dx and C_ = df/dv of the total force at (x, v), by finite differences.
  void differenceJacobians(const System& system, double h, const Eigen::VectorXd& x,
                           const Eigen::VectorXd& v, SparseMatrix& A);
  // The velocity part of A (h c - h C_, or -h C_ with finite differences) times v, into out.
  void velocityTermTimes(const System& system, double h, const Eigen::VectorXd& v,
                         Eigen::VectorXd& out) const;
  // Solves A x = b (x holds the initial guess); returns the iterations used.
  int solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  int solveUnit(const Eigen::VectorXd& b, Eigen::VectorXd& x);  // max |b_i| = 1
  int solvePcg(const Preconditioner& M, const Eigen::VectorXd& b, Eigen::VectorXd& x);
  SolveSettings solveSettings() const {
    return {params.linearTolerance, params.linearMaxIterations, params.gmresRestart};
  }
  // With Cholesky or AMG and none installed: builds it from A_ now. When A_ is refused (not
  // positive definite: a stiffness softened by compression) it is built from the matrix with
  // the models' PSD-projected stiffness at the same state, and so are the factors after it;
  // without a projection, from the rest shape's matrix. All constrained as A_ is.
  void ensureFactor(const System& system, double h);
  // The matrix a factor is built from now: A_, or after a refusal the projected matrix of the
  // step being taken (stepSystem_, stepH_).
  const SparseMatrix& factorMatrix();
  // The preconditioner for A_ in this solve: the factor or hierarchy when installed, else
  // Jacobi.
  const Preconditioner& choosePreconditioner();
  // After a solve of `iterations`: starts a new factor or hierarchy of A_ when it was slow.
  void considerRefactor(int iterations, bool lostCurvature);
  void noteRefusals();  // copies the build counts into diagnostics_, noting new refusals
  int finishSolve(const SolveReport& report, int earlierIterations, bool lostCurvature);

  BackwardEulerDiagnostics diagnostics_;
  SparseMatrix A_, C_, restA_, projectedA_;
  bool projectFactors_ = false;        // a factor of A_ was refused: factor projectedA_
  const System* stepSystem_ = nullptr;  // the step being taken (attempt), for factorMatrix
  double stepH_ = 0.0;
  std::vector<int> diagonal_;  // offset of (i, i) in the value array of the system pattern
  Eigen::VectorXd dv_, f_, rhs_, constrainedDv_, residual_, correction_;
  Eigen::VectorXd unitB_, guess_, diagonalValues_;
  JacobiPreconditioner jacobi_;
  std::unique_ptr<RebuiltPreconditioner> rebuilt_;  // with kCholesky or kAmg
  int solvesSinceRefusal_ = 0;  // since the last refused factorisation
  KrylovWorkspace krylov_;
  Eigen::VectorXd x1_, v1_, targetX_, targetV_;
  std::unique_ptr<FiniteDifferenceJacobian> differences_;  // with kFiniteDifference
  Eigen::VectorXd differenceForce_;
  double lastStep_ = 0.0;  // of the last attempt (the warm start's scale)
};

}  // namespace tt
