#pragma once
// Algebraic multigrid as the preconditioner of CG: hypre's BoomerAMG hierarchy of a recent
// system matrix, applied as one V-cycle from a zero guess (z = M^-1 r, a fixed linear map, so
// CG may use it). As with the Cholesky factor, an implicit step's matrix changes slowly from
// step to step and the hierarchy of one matrix serves the ones after it; the caller asks for a
// new one when the iterations rise. Unlike the factor, the set-up is always synchronous (it
// runs in rebuild(), on the caller's thread) and it does not ask for a positive definite
// matrix: an indefinite one gets a hierarchy too, and CG will say so.
//
// Defaults for 3-D elasticity (hypre's reference manual, BoomerAMG section): HMIS coarsening
// with strong threshold 0.5, extended+i interpolation truncated to 4 entries per row, systems
// AMG by the unknown approach (3 functions, DOFs node-major x, y, z: a coupling between two
// different components is never strong), l1-scaled symmetric Gauss-Seidel on the way down and
// up (one process: plain symmetric Gauss-Seidel) and Gaussian elimination on the coarsest
// level. The V-cycle is then symmetric positive definite for a symmetric positive definite A.
//
// hypre in Debian is built with MPI and without OpenMP: the first instance initialises MPI
// (a singleton process; OpenMPI starts its helper daemon for it) unless the program has, and
// BoomerAMG runs on the calling thread whatever tt::threadCount() says. A hypre error does not
// abort: it is a refused set-up (the previous hierarchy is gone; ready() is false) or, in
// apply(), z = r for the rest of that solve; lastRefusal() says what hypre reported.
#include <Eigen/Core>
#include <memory>
#include <string>

#include "tissue_trainer/core/solve/krylov.h"

namespace tt {

struct AmgSettings {
  double strongThreshold = 0.5;  // hypre's 0.25 suits 2-D; 0.5 to 0.6 for 3-D
  int numFunctions = 3;          // unknowns per node (1: scalar AMG)
  int coarsenType = 10;          // 10 HMIS, 8 PMIS, 6 Falgout
  int interpMaxElements = 4;     // interpolation entries per row
  int aggressiveLevels = 0;      // levels of aggressive coarsening (cheaper, weaker)
  int relaxType = 8;             // 8 l1 symmetric Gauss-Seidel, 6 hybrid symmetric GS
  int maxLevels = 25;
};

class AmgPreconditioner final : public RebuiltPreconditioner {
 public:
  explicit AmgPreconditioner(const AmgSettings& settings = {});
  ~AmgPreconditioner() override;
  AmgPreconditioner(const AmgPreconditioner&) = delete;
  AmgPreconditioner& operator=(const AmgPreconditioner&) = delete;

  // Builds the hierarchy of the square matrix A (copied into hypre: A may change at once).
  // False on a hypre error (lastRefusal()), and then no hierarchy serves.
  bool setup(const SparseMatrix& A);
  bool rebuild(const SparseMatrix& A) override { return setup(A); }
  bool rebuildNow(const SparseMatrix& A) override { return setup(A); }
  bool update() override { return false; }  // nothing runs in the background

  bool ready() const override { return ready_; }
  bool busy() const override { return false; }
  int builds() const override { return setups_; }
  int refusals() const override { return failures_; }  // failed set-ups and V-cycles
  const std::string& lastRefusal() const override { return lastError_; }

  // One V-cycle on A z = r from z = 0 (z = r when no hierarchy serves).
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override;

  struct Hypre;

 private:
  bool fail(const char* call, int code) const;

  AmgSettings settings_;
  std::unique_ptr<Hypre> hypre_;
  mutable bool ready_ = false;
  mutable int failures_ = 0;
  mutable std::string lastError_;
  int setups_ = 0;
};

}  // namespace tt
