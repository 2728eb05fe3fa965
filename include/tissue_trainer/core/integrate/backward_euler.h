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
// Preconditioners: Jacobi, the sparse Cholesky factor of an earlier system matrix, or a
// BoomerAMG hierarchy of one, kept and rebuilt by the rule of solve/linear_solve.h
// (LinearSolveRule::timeStepping): the first step factors its own matrix, a solve that needs
// more than refactorIterations iterations (or meets non-positive curvature) starts a new factor
// that takes over at the start of a later step (in the background when backgroundRefactor;
// AMG always synchronously), Jacobi serves while there is none, and a refused factorisation
// falls back to the matrix with the models' PSD-projected stiffness, then to the rest shape's.
#include <Eigen/Core>
#include <limits>
#include <memory>
#include <string>

#include "tissue_trainer/core/integrate/step_control.h"
#include "tissue_trainer/core/integrate/stepped_integrator.h"
#include "tissue_trainer/core/solve/finite_difference_jacobian.h"
#include "tissue_trainer/core/solve/linear_solve.h"

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
  using Preconditioning = PreconditionerKind;
  Preconditioning preconditioner = Preconditioning::kCholesky;
  int refactorIterations = 15;    // cholesky, amg: a solve that needs more starts a new one (0: every solve)
  bool backgroundRefactor = true;  // cholesky: factorise on a thread of its own
  CholeskyBackend choleskyBackend = CholeskyBackend::kCholmod;
  AmgSettings amg;                // amg: BoomerAMG's options
  using LinearSolver = LinearMethod;
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

  // The linear solve's part of these parameters.
  LinearSolveSettings linearSolve() const;
  void setLinearSolve(const LinearSolveSettings& settings);
};

// The controller of the iteration-count step control for these parameters (adaptive).
HalvingDoublingParams iterationStepControl(const BackwardEulerParams& params);

// Counts over the integrator's life (not per frame): the linear solve's
// (LinearSolveDiagnostics: nonPositiveCurvature counts the CG solves redone with BiCGSTAB) and
// the integrator's own.
struct BackwardEulerDiagnostics : LinearSolveDiagnostics {
  int unconvergedNewton = 0;          // steps whose Newton loop hit newtonIterations (> 1)
  long jacobianForceEvaluations = 0;  // force evaluations of finite-difference Jacobians
};

class BackwardEulerIntegrator : public SteppedIntegrator, private FactorFallbacks {
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
  void copyLinearDiagnostics();
  // The matrices the linear solve falls back on when A_ cannot be factored: with the models'
  // PSD-projected stiffness at the state of the step being taken (stepSystem_, stepH_), and
  // at the rest shape. Both constrained as A_ is.
  bool canProject() const override;
  const SparseMatrix& projectedMatrix() override;
  const SparseMatrix& restMatrix() override;

  BackwardEulerDiagnostics diagnostics_;
  SparseMatrix A_, C_, restA_, projectedA_;
  LinearSolve linear_;
  const System* stepSystem_ = nullptr;  // the step being taken (attempt), for the fallbacks
  double stepH_ = 0.0;
  std::vector<int> diagonal_;  // offset of (i, i) in the value array of the system pattern
  Eigen::VectorXd dv_, f_, rhs_, constrainedDv_, residual_, correction_;
  Eigen::VectorXd unitB_;
  Eigen::VectorXd x1_, v1_, targetX_, targetV_;
  std::unique_ptr<FiniteDifferenceJacobian> differences_;  // with kFiniteDifference
  Eigen::VectorXd differenceForce_;
  double lastStep_ = 0.0;  // of the last attempt (the warm start's scale)
};

}  // namespace tt
