#include "tissue_trainer/core/solve/cholesky_preconditioner.h"

#include <dlfcn.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <utility>

namespace tt {

namespace {

using ColumnMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// A symmetric row-major matrix read as column-major is the same matrix (its transpose).
Eigen::Map<const ColumnMatrix> asColumnMajor(const SparseMatrix& A) {
  return {A.rows(), A.cols(), A.nonZeros(), A.outerIndexPtr(), A.innerIndexPtr(),
          A.valuePtr()};
}

// CHOLMOD calls BLAS from the factorising thread and from the solving one at once. OpenBLAS is
// safe for that only in its threaded build (the serial one has no locks), whose own threads
// would then compete with the haptic loop: one thread each, in the caller. Other BLAS
// libraries have no such call and are left as they are.
void keepBlasInTheCallingThread() {
  static const bool once = [] {
    using SetThreads = void (*)(int);
    if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
      set(1);
    return true;
  }();
  (void)once;
}

}  // namespace

// One factorisation; the symbolic analysis is done once per sparsity pattern.
struct CholeskyPreconditioner::Factor {
  virtual ~Factor() = default;
  virtual bool factor(const Eigen::Map<const ColumnMatrix>& A) = 0;  // false: not SPD
  virtual void solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) const = 0;

  // Whether A has the pattern the analysis was made for.
  bool samePattern(const Eigen::Map<const ColumnMatrix>& A) {
    const bool same = A.rows() == rows && A.nonZeros() == nonZeros;
    rows = A.rows();
    nonZeros = A.nonZeros();
    return same;
  }
  Eigen::Index rows = -1, nonZeros = -1;
};

namespace {

// L D L^T with Eigen's AMD ordering; positive definite when every pivot of D is > 0.
struct SimplicialFactor final : CholeskyPreconditioner::Factor {
  bool factor(const Eigen::Map<const ColumnMatrix>& A) override {
    if (!samePattern(A)) ldlt.analyzePattern(A);
    ldlt.factorize(A);
    if (ldlt.info() != Eigen::Success) return false;
    const Eigen::VectorXd& d = ldlt.vectorD();
    return d.allFinite() && (d.array() > 0.0).all();
  }
  void solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override { z = ldlt.solve(r); }
  Eigen::SimplicialLDLT<ColumnMatrix, Eigen::Lower> ldlt;
};

// CHOLMOD's supernodal L L^T: it stops at the first non-positive pivot. (Its automatic mode
// picks a simplicial L D L^T for small matrices, which factors indefinite ones without a word.)
struct CholmodFactor final : CholeskyPreconditioner::Factor {
  CholmodFactor() {
    llt.setMode(Eigen::CholmodSupernodalLLt);
    llt.cholmod().print = 0;  // a refused matrix is reported, not printed
  }
  bool factor(const Eigen::Map<const ColumnMatrix>& A) override {
    if (!samePattern(A)) llt.analyzePattern(A);
    llt.factorize(A);
    return llt.info() == Eigen::Success;
  }
  void solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override { z = llt.solve(r); }
  Eigen::CholmodDecomposition<ColumnMatrix, Eigen::Lower> llt;
};

std::unique_ptr<CholeskyPreconditioner::Factor> makeFactor(CholeskyBackend backend) {
  if (backend == CholeskyBackend::kCholmod) return std::make_unique<CholmodFactor>();
  return std::make_unique<SimplicialFactor>();
}

}  // namespace

const char* backendName(CholeskyBackend backend) {
  return backend == CholeskyBackend::kCholmod ? "cholmod" : "eigen_simplicial_ldlt";
}

CholeskyPreconditioner::CholeskyPreconditioner(bool background, CholeskyBackend backend)
    : background_(background), active_(makeFactor(backend)), pending_(makeFactor(backend)) {
  keepBlasInTheCallingThread();
}

CholeskyPreconditioner::~CholeskyPreconditioner() {
  if (worker_.joinable()) worker_.join();
}

bool CholeskyPreconditioner::refactor(const SparseMatrix& A) {
  if (busy_) return false;
  copy_ = A;
  if (!background_) return finish(pending_->factor(asColumnMajor(copy_)));
  busy_ = true;
  done_.store(false, std::memory_order_relaxed);
  worker_ = std::thread([this] {
    pendingOk_ = pending_->factor(asColumnMajor(copy_));
    done_.store(true, std::memory_order_release);
  });
  return true;
}

bool CholeskyPreconditioner::factorNow(const SparseMatrix& A) {
  wait();
  return finish(pending_->factor(asColumnMajor(A)));
}

bool CholeskyPreconditioner::update() {
  if (!busy_ || !done_.load(std::memory_order_acquire)) return false;
  worker_.join();
  busy_ = false;
  return finish(pendingOk_);
}

bool CholeskyPreconditioner::wait() {
  if (!busy_) return false;
  worker_.join();
  busy_ = false;
  return finish(pendingOk_);
}

bool CholeskyPreconditioner::finish(bool positiveDefinite) {
  if (!positiveDefinite) {
    ++refused_;
    lastRefusal_ = "Cholesky factorisation: the matrix is not positive definite";
    return false;
  }
  lastRefusal_.clear();
  std::swap(active_, pending_);
  installed_ = true;
  ++factorizations_;
  return true;
}

void CholeskyPreconditioner::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  if (installed_)
    active_->solve(r, z);
  else
    z = r;
}

}  // namespace tt
