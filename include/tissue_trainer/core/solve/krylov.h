#pragma once
// Krylov solvers for A x = b on an assembled matrix or a matrix-free operator, behind one
// preconditioner interface: preconditioned conjugate gradients (A symmetric positive
// definite), BiCGSTAB and restarted GMRES (any non-singular A). Each returns a report of
// what happened; none allocates once its workspace has the system's size.
//
// Every solver starts from the x it is given (a warm start) and stops when
// |b - A x| <= tolerance * |b| (2-norms) or after maxIterations operator applications.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "tissue_trainer/core/solve/sparse_pattern.h"

namespace tt {

// y = A x. One virtual call per application, never per entry.
class LinearOperator {
 public:
  virtual ~LinearOperator() = default;
  virtual Eigen::Index size() const = 0;
  virtual void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const = 0;
};

class MatrixOperator final : public LinearOperator {
 public:
  explicit MatrixOperator(const SparseMatrix& A) : A_(A) {}
  Eigen::Index size() const override { return A_.rows(); }
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override { y.noalias() = A_ * x; }

 private:
  const SparseMatrix& A_;
};

// z = M^-1 r for a preconditioner M close to A.
class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  virtual void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const = 0;
};

// A preconditioner made from a matrix (a factor, a multigrid hierarchy) that is rebuilt from a
// recent matrix now and then: what the implicit integrators hold to precondition a sequence
// of slowly changing system matrices.
class RebuiltPreconditioner : public Preconditioner {
 public:
  // Starts a build from A (on a thread of its own where the class can); false when none was
  // started, or when a synchronous build was refused.
  virtual bool rebuild(const SparseMatrix& A) = 0;
  // Builds from A on this thread and installs the result; false when refused.
  virtual bool rebuildNow(const SparseMatrix& A) = 0;
  // Installs a finished background build; true when a new one took over.
  virtual bool update() = 0;
  virtual bool ready() const = 0;  // a build serves apply()
  virtual bool busy() const = 0;   // a build is running
  virtual int builds() const = 0;    // installed so far
  virtual int refusals() const = 0;  // refused so far
  // Why the last build was refused; empty when none was, or after a build succeeded.
  virtual const std::string& lastRefusal() const = 0;
};

class IdentityPreconditioner final : public Preconditioner {
 public:
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override { z = r; }
};

// M = diag(A). setDiagonal returns false (and keeps the identity there) where an entry is
// zero or not finite; positive() tells whether every entry was > 0 (what CG wants).
class JacobiPreconditioner final : public Preconditioner {
 public:
  bool setDiagonal(const Eigen::VectorXd& diagonal);
  bool setFromMatrix(const SparseMatrix& A);
  bool positive() const { return positive_; }
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override {
    z = inverse_.cwiseProduct(r);
  }

 private:
  Eigen::VectorXd inverse_;
  bool positive_ = false;
};

struct SolveSettings {
  double tolerance = 1e-8;   // relative to |b|
  int maxIterations = 1000;  // operator applications
  int restart = 30;          // GMRES: Krylov vectors per cycle
};

enum class SolveOutcome {
  kConverged,
  kMaxIterations,         // stopped with the residual above the tolerance
  kNonPositiveCurvature,  // CG: p . A p <= 0 (A is not positive definite)
  kBreakdown,             // BiCGSTAB or GMRES: a zero denominator
};

const char* outcomeName(SolveOutcome outcome);

struct SolveReport {
  int iterations = 0;
  double relativeResidual = 0.0;  // |b - A x| / |b| at the returned x (recursive estimate)
  SolveOutcome outcome = SolveOutcome::kConverged;
  bool converged() const { return outcome == SolveOutcome::kConverged; }
};

// Vectors the solvers keep between calls.
struct KrylovWorkspace {
  Eigen::VectorXd r, z, p, q, s, t, v, y;
  Eigen::VectorXd shadow;  // BiCGSTAB: the fixed shadow residual r0^
  std::vector<Eigen::VectorXd> basis;  // GMRES
  Eigen::MatrixXd hessenberg;
  Eigen::VectorXd cosines, sines, g;
};

SolveReport conjugateGradients(const LinearOperator& A, const Eigen::VectorXd& b,
                               Eigen::VectorXd& x, const Preconditioner& M,
                               const SolveSettings& settings, KrylovWorkspace& work);
SolveReport biCgStab(const LinearOperator& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                     const Preconditioner& M, const SolveSettings& settings,
                     KrylovWorkspace& work);
// Right-preconditioned: the residual it tests is the true one, b - A x.
SolveReport gmres(const LinearOperator& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                  const Preconditioner& M, const SolveSettings& settings, KrylovWorkspace& work);

}  // namespace tt
