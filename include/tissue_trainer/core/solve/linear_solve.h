#pragma once
// One linear solve A x = b of an implicit method, repeated with slowly changing matrices, and
// the rule that keeps its preconditioner between the solves. Backward Euler, the equilibrium
// solver and its pseudo-time recovery each hold one; none of them decides on factors itself.
//
// The preconditioner is Jacobi, or a factor kept from an earlier matrix: a sparse Cholesky
// factor (solve/cholesky_preconditioner.h) or a BoomerAMG hierarchy
// (solve/amg_preconditioner.h). The rule:
// - A solve that needs more than refactorIterations iterations with the kept factor, or meets
//   non-positive curvature with one that is not projected, asks for a new factor of its
//   matrix (0: a new factor for every solve). What then happens is the caller's choice
//   (LinearSolveRule): the time steppers keep the slow answer and the new factor serves the
//   solves after it (built in the background where backgroundRefactor allows); the Newton
//   solver cuts the kept factor's try at refactorIterations and solves again with a new
//   factor of the same matrix at once.
// - Jacobi preconditions while no factor serves (time steppers).
// - A refused factorisation (a matrix that is not positive definite, or a hypre error) keeps
//   the old factor, and the next try waits retryAfterRefusal solves. Where the caller offers
//   them (FactorFallbacks), the refused matrix is replaced by the matrix with the models'
//   PSD-projected stiffness at the same state (and so are the later ones), then by the matrix
//   of the rest shape.
// - Where PCG meets non-positive curvature (or Jacobi a non-positive diagonal) the time
//   steppers solve again with BiCGSTAB from the same guess; the Newton solver is told, and
//   shifts its matrix.
#include <Eigen/Core>
#include <memory>
#include <string>

#include "tissue_trainer/core/solve/amg_preconditioner.h"
#include "tissue_trainer/core/solve/cholesky_preconditioner.h"
#include "tissue_trainer/core/solve/krylov.h"

namespace tt {

enum class LinearMethod { kPcg, kGmres, kBiCgStab };
enum class PreconditionerKind { kJacobi, kCholesky, kAmg };

const char* methodName(LinearMethod method);
const char* preconditionerName(PreconditionerKind kind);

// What a scene sets: the integrator keys of solve/linear_solve_keys.h. The defaults here are
// neutral; each integrator states its own.
struct LinearSolveSettings {
  LinearMethod method = LinearMethod::kPcg;
  int gmresRestart = 30;             // kGmres: Krylov vectors per cycle
  double tolerance = 1e-8;           // relative residual |b - A x| / |b|
  int maxIterations = 1000;
  PreconditionerKind preconditioner = PreconditionerKind::kJacobi;
  int refactorIterations = 15;       // a solve that needs more asks for a new factor
  bool backgroundRefactor = false;   // Cholesky: factorise on a thread of its own
  CholeskyBackend choleskyBackend = CholeskyBackend::kCholmod;
  AmgSettings amg;
};

bool operator==(const LinearSolveSettings& a, const LinearSolveSettings& b);
inline bool operator!=(const LinearSolveSettings& a, const LinearSolveSettings& b) {
  return !(a == b);
}

// What the caller decides (no scene key): when a slow solve's new factor takes over, how long a
// refused factorisation waits, and what non-positive curvature leads to.
struct LinearSolveRule {
  enum class AfterSlowSolve {
    kRefactorForLaterSolves,  // keep the answer; the new factor serves the next solves
    kSolveAgainWithNewFactor,  // the kept factor's try stops at refactorIterations
  };
  AfterSlowSolve afterSlowSolve = AfterSlowSolve::kRefactorForLaterSolves;
  int retryAfterRefusal = 10;  // solves between a refused factorisation and the next try
  bool biCgStabOnLostCurvature = true;  // false: report it (LinearSolveReport::lostCurvature)

  // Backward Euler: one answer per solve, a factor for the steps to come.
  static LinearSolveRule timeStepping() { return {}; }
  // Newton directions: the answer must come from a good factor (kept or new), and an
  // indefinite matrix is the caller's to shift.
  static LinearSolveRule newtonDirections() {
    return {AfterSlowSolve::kSolveAgainWithNewFactor, 0, false};
  }
};

// Matrices a caller can offer in place of its own when that one's factorisation is refused.
class FactorFallbacks {
 public:
  virtual ~FactorFallbacks() = default;
  // Whether projectedMatrix() exists (the models project their stiffness to PSD).
  virtual bool canProject() const = 0;
  // The matrix at the same state with the models' PSD-projected stiffness.
  virtual const SparseMatrix& projectedMatrix() = 0;
  // The matrix of the rest shape (positive definite).
  virtual const SparseMatrix& restMatrix() = 0;
};

struct LinearSolveReport {
  int iterations = 0;  // all of this solve's tries (CG before BiCGSTAB, a kept factor's before a new one's)
  double relativeResidual = 0.0;
  SolveOutcome outcome = SolveOutcome::kConverged;
  bool lostCurvature = false;  // CG met non-positive curvature, or Jacobi a non-positive diagonal
  bool refused = false;        // no factor could be made for the matrix: nothing was solved
  bool converged() const { return outcome == SolveOutcome::kConverged && !refused; }
};

// Counts over the object's life.
struct LinearSolveDiagnostics {
  int nonPositiveCurvature = 0;  // solves whose CG met non-positive curvature
  int unconvergedLinear = 0;     // solves that ended above the tolerance
  double lastRelativeResidual = 0.0;  // |b - A x| / |b| reached by the last solve
  int lastIterations = 0;             // of the last solve
  int factorizations = 0;             // Cholesky factors installed or AMG hierarchies set up
  int notPositiveDefinite = 0;        // matrices the Cholesky factorisation refused
  int projectedFactors = 0;           // factors built from the PSD-projected matrix
  int amgFailures = 0;                // AMG set-ups and V-cycles that hypre failed
  std::string lastRefusal;            // why the last refused factorisation was refused
  int jacobiFallbacks = 0;            // solves preconditioned by Jacobi for want of a factor
};

class LinearSolve {
 public:
  explicit LinearSolve(LinearSolveSettings settings = {},
                       LinearSolveRule rule = LinearSolveRule::timeStepping());
  LinearSolve(LinearSolve&&) = default;
  LinearSolve& operator=(LinearSolve&&) = default;

  const LinearSolveSettings& settings() const { return settings_; }
  const LinearSolveRule& rule() const { return rule_; }
  // New settings; the kept factor is dropped when they differ from the present ones.
  void configure(const LinearSolveSettings& settings);

  // Time steppers, at the start of a step: a factor finished in the background takes over.
  void installFinishedFactor();
  // Time steppers, with the step's first matrix: when no factor serves (and no refusal is
  // waiting out retryAfterRefusal), factors A now, or one of the fallbacks.
  void ensureFactor(const SparseMatrix& A, FactorFallbacks* fallbacks = nullptr);

  // Solves A x = b from the guess in x. b = 0 gives x = 0 at once.
  LinearSolveReport solve(const SparseMatrix& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                          FactorFallbacks* fallbacks = nullptr);

  // The kept factor or hierarchy when one serves a matrix of `rows` rows; null otherwise.
  const Preconditioner* factor(Eigen::Index rows) const;
  const LinearSolveDiagnostics& diagnostics() const { return diagnostics_; }

 private:
  bool usesFactors() const { return settings_.preconditioner != PreconditionerKind::kJacobi; }
  void makeFactorHolder();
  bool waitingAfterRefusal() const { return solvesSinceRefusal_ < rule_.retryAfterRefusal; }
  // The matrix a factor is built from: A, or after a refusal the projected one.
  const SparseMatrix& factorMatrix(const SparseMatrix& A, FactorFallbacks* fallbacks);
  // Factors A (or the fallbacks, in order) on this thread; false when every one was refused.
  bool factorNowOrFallBack(const SparseMatrix& A, FactorFallbacks* fallbacks);
  bool buildNow(const SparseMatrix& A);
  void noteBuilds();  // copies the factor's counts, and starts the wait after a new refusal
  const Preconditioner& jacobiOf(const SparseMatrix& A);

  LinearSolveReport solveKeepingAnswer(const SparseMatrix& A, const Eigen::VectorXd& b,
                                       Eigen::VectorXd& x, FactorFallbacks* fallbacks);
  LinearSolveReport solveWithGoodFactor(const SparseMatrix& A, const Eigen::VectorXd& b,
                                        Eigen::VectorXd& x, FactorFallbacks* fallbacks);
  // The method with preconditioner M, at most maxIterations (PCG's curvature fallback
  // included).
  LinearSolveReport krylov(const SparseMatrix& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                           const Preconditioner& M, int maxIterations);
  void considerRefactor(const SparseMatrix& A, const LinearSolveReport& report,
                        FactorFallbacks* fallbacks);
  LinearSolveReport finish(LinearSolveReport report);

  LinearSolveSettings settings_;
  LinearSolveRule rule_;
  LinearSolveDiagnostics diagnostics_;
  std::unique_ptr<RebuiltPreconditioner> factor_;
  Eigen::Index factorRows_ = -1;  // of the matrix the kept factor was made from
  bool projecting_ = false;       // a refusal switched the factors to the projected matrix
  int solvesSinceRefusal_ = 0;
  JacobiPreconditioner jacobi_;
  Eigen::VectorXd diagonal_, guess_;
  KrylovWorkspace workspace_;
};

}  // namespace tt
