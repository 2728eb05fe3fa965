#pragma once
// A sparse Cholesky factor of a recent system matrix, used as the preconditioner of CG for the
// matrices that follow it. An implicit step's matrix M + h C - h^2 K changes slowly from step
// to step, so the factor of one matrix stays a close approximation of the next ones: CG then
// needs a few iterations where Jacobi needs hundreds on a mesh whose element sizes vary
// widely. When the iterations rise the caller asks for a new factor; that factorisation can
// run on a thread of its own (the other core) while the old factor keeps serving, and the new
// one takes over only when the caller calls update() (between steps, never inside a solve).
//
// Backends: CHOLMOD (SuiteSparse, through Eigen's CholmodSupport; supernodal L L^T) and
// Eigen's SimplicialLDLT, kept for comparison in the benchmarks. A matrix that is not positive
// definite is refused: the previous factor stays in use, or none is installed.
#include <Eigen/Core>
#include <atomic>
#include <memory>
#include <thread>

#include "tissue_trainer/core/solve/krylov.h"

namespace tt {

enum class CholeskyBackend { kEigenSimplicial, kCholmod };

const char* backendName(CholeskyBackend backend);

class CholeskyPreconditioner final : public RebuiltPreconditioner {
 public:
  // background: factorisations started by refactor() run on a thread of their own.
  explicit CholeskyPreconditioner(bool background = true,
                                  CholeskyBackend backend = CholeskyBackend::kCholmod);
  ~CholeskyPreconditioner() override;
  CholeskyPreconditioner(const CholeskyPreconditioner&) = delete;
  CholeskyPreconditioner& operator=(const CholeskyPreconditioner&) = delete;

  // Starts a factorisation of the symmetric matrix A (copied, so A may change at once); does
  // nothing and returns false while an earlier one is still running. Synchronous mode: the
  // factor is made and installed before it returns, and false says A was refused.
  bool refactor(const SparseMatrix& A);
  // Waits for a running factorisation, then factors A on this thread and installs it when
  // positive definite (returns whether it did).
  bool factorNow(const SparseMatrix& A);
  // Installs a finished background factorisation. True when a new factor took over.
  bool update() override;
  // Waits for a running factorisation, then update().
  bool wait();

  bool ready() const override { return installed_; }  // a factor serves apply()
  bool busy() const override { return busy_; }          // a factorisation is running
  int factorizations() const { return factorizations_; }   // installed so far
  int notPositiveDefinite() const { return refused_; }     // refused so far

  bool rebuild(const SparseMatrix& A) override { return refactor(A); }
  bool rebuildNow(const SparseMatrix& A) override { return factorNow(A); }
  int builds() const override { return factorizations_; }
  int refusals() const override { return refused_; }
  const std::string& lastRefusal() const override { return lastRefusal_; }

  // z = L^-T D^-1 L^-1 r for the installed factor (r itself when none is installed).
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override;

  struct Factor;

 private:
  bool finish(bool positiveDefinite);

  bool background_;
  std::unique_ptr<Factor> active_, pending_;
  SparseMatrix copy_;
  std::thread worker_;
  std::atomic<bool> done_{false};
  bool busy_ = false, pendingOk_ = false, installed_ = false;
  int factorizations_ = 0, refused_ = 0;
  std::string lastRefusal_;
};

}  // namespace tt
