#include "tissue_trainer/core/solve/amg_preconditioner.h"

#include <mpi.h>

#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <mutex>
#include <vector>

namespace tt {

namespace {

// hypre's IJ interface asks MPI for the size of the communicator even on one process, so MPI
// must be initialised before the first call (and not yet finalised).
bool mpiReady(std::string& why) {
  static std::once_flag once;
  std::call_once(once, [] {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) {
      int provided = 0;
      MPI_Init_thread(nullptr, nullptr, MPI_THREAD_MULTIPLE, &provided);
    }
    HYPRE_Init();
  });
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (finalised) why = "MPI has been finalised; hypre cannot run";
  return !finalised;
}

}  // namespace

// The hypre objects: the matrix of the last set-up, the two vectors of a V-cycle and the
// solver holding the hierarchy, which refers to all three.
struct AmgPreconditioner::Hypre {
  ~Hypre() {
    destroySolver();
    destroyMatrix();
    if (rhs) HYPRE_IJVectorDestroy(rhs);
    if (solution) HYPRE_IJVectorDestroy(solution);
  }
  void destroySolver() {
    if (solver) HYPRE_BoomerAMGDestroy(solver);
    solver = nullptr;
  }
  void destroyMatrix() {
    if (matrix) HYPRE_IJMatrixDestroy(matrix);
    matrix = nullptr;
  }

  HYPRE_IJMatrix matrix = nullptr;
  HYPRE_ParCSRMatrix parMatrix = nullptr;
  HYPRE_IJVector rhs = nullptr, solution = nullptr;
  HYPRE_ParVector parRhs = nullptr, parSolution = nullptr;
  HYPRE_Solver solver = nullptr;
  std::vector<HYPRE_BigInt> rows, columns;  // rows = 0 .. n-1: also the vectors' indices
  std::vector<HYPRE_Int> rowSizes;
  bool broken = false;  // an error left the solver in an unknown state
};

AmgPreconditioner::AmgPreconditioner(const AmgSettings& settings)
    : settings_(settings), hypre_(std::make_unique<Hypre>()) {}

AmgPreconditioner::~AmgPreconditioner() = default;

bool AmgPreconditioner::fail(const char* call, int code) const {
  char description[256] = "";
  HYPRE_DescribeError(code, description);
  lastError_ = std::string("hypre ") + call + " failed: " + description;
  HYPRE_ClearAllErrors();  // hypre's error flag is global and sticky
  hypre_->broken = true;
  ready_ = false;
  ++failures_;
  return false;
}

bool AmgPreconditioner::setup(const SparseMatrix& A) {
  Hypre& h = *hypre_;
  ready_ = false;
  if (!mpiReady(lastError_)) return ++failures_, false;
  if (A.rows() != A.cols() || A.rows() == 0) {
    lastError_ = "AMG set-up: expected a non-empty square matrix, got " +
                 std::to_string(A.rows()) + " x " + std::to_string(A.cols());
    return ++failures_, false;
  }
  const int n = static_cast<int>(A.rows());
  if (h.broken) h.destroySolver();
  h.broken = false;
  int code = 0;
  const auto ok = [&code](int c) { return (code = c) == 0; };

  if (static_cast<int>(h.rows.size()) != n) {
    h.destroySolver();  // it refers to the old vectors
    for (HYPRE_IJVector* v : {&h.rhs, &h.solution}) {
      if (*v) HYPRE_IJVectorDestroy(*v);
      *v = nullptr;
      if (!ok(HYPRE_IJVectorCreate(MPI_COMM_SELF, 0, n - 1, v)) ||
          !ok(HYPRE_IJVectorSetObjectType(*v, HYPRE_PARCSR)) ||
          !ok(HYPRE_IJVectorInitialize(*v)) || !ok(HYPRE_IJVectorAssemble(*v)))
        return fail("IJVector creation", code);
    }
    HYPRE_IJVectorGetObject(h.rhs, reinterpret_cast<void**>(&h.parRhs));
    HYPRE_IJVectorGetObject(h.solution, reinterpret_cast<void**>(&h.parSolution));
    h.rows.resize(n);
    for (int i = 0; i < n; ++i) h.rows[i] = i;
  }

  // A fresh copy of A (a CSR matrix, as SparseMatrix is): the hierarchy's finest level.
  h.rowSizes.resize(n);
  for (int i = 0; i < n; ++i) h.rowSizes[i] = A.outerIndexPtr()[i + 1] - A.outerIndexPtr()[i];
  h.columns.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  h.destroyMatrix();
  if (!ok(HYPRE_IJMatrixCreate(MPI_COMM_SELF, 0, n - 1, 0, n - 1, &h.matrix)) ||
      !ok(HYPRE_IJMatrixSetObjectType(h.matrix, HYPRE_PARCSR)) ||
      !ok(HYPRE_IJMatrixSetRowSizes(h.matrix, h.rowSizes.data())) ||
      !ok(HYPRE_IJMatrixInitialize(h.matrix)) ||
      !ok(HYPRE_IJMatrixSetValues(h.matrix, n, h.rowSizes.data(), h.rows.data(),
                                  h.columns.data(), A.valuePtr())) ||
      !ok(HYPRE_IJMatrixAssemble(h.matrix)) ||
      !ok(HYPRE_IJMatrixGetObject(h.matrix, reinterpret_cast<void**>(&h.parMatrix))))
    return fail("IJMatrix assembly", code);

  if (!h.solver) {
    const AmgSettings& s = settings_;
    if (!ok(HYPRE_BoomerAMGCreate(&h.solver)) || !ok(HYPRE_BoomerAMGSetPrintLevel(h.solver, 0)) ||
        !ok(HYPRE_BoomerAMGSetMaxIter(h.solver, 1)) ||  // a preconditioner: one V-cycle,
        !ok(HYPRE_BoomerAMGSetTol(h.solver, 0.0)) ||    // no residual norm
        !ok(HYPRE_BoomerAMGSetCoarsenType(h.solver, s.coarsenType)) ||
        !ok(HYPRE_BoomerAMGSetStrongThreshold(h.solver, s.strongThreshold)) ||
        !ok(HYPRE_BoomerAMGSetInterpType(h.solver, 6)) ||  // extended+i
        !ok(HYPRE_BoomerAMGSetPMaxElmts(h.solver, s.interpMaxElements)) ||
        !ok(HYPRE_BoomerAMGSetAggNumLevels(h.solver, s.aggressiveLevels)) ||
        !ok(HYPRE_BoomerAMGSetNumFunctions(h.solver, s.numFunctions)) ||
        !ok(HYPRE_BoomerAMGSetRelaxType(h.solver, s.relaxType)) ||
        !ok(HYPRE_BoomerAMGSetMaxLevels(h.solver, s.maxLevels)))
      return fail("BoomerAMG configuration", code);
  }
  // A second set-up on the same solver frees the old hierarchy first.
  if (!ok(HYPRE_BoomerAMGSetup(h.solver, h.parMatrix, h.parRhs, h.parSolution)))
    return fail("BoomerAMGSetup", code);
  ready_ = true;
  ++setups_;
  lastError_.clear();
  return true;
}

void AmgPreconditioner::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  Hypre& h = *hypre_;
  const int n = static_cast<int>(h.rows.size());
  if (!ready_ || r.size() != n) {
    z = r;
    return;
  }
  z.resize(n);
  int code = 0;
  const auto ok = [&code](int c) { return (code = c & ~HYPRE_ERROR_CONV) == 0; };
  if (!ok(HYPRE_IJVectorSetValues(h.rhs, n, h.rows.data(), r.data())) ||
      !ok(HYPRE_ParVectorSetConstantValues(h.parSolution, 0.0)) ||
      !ok(HYPRE_BoomerAMGSolve(h.solver, h.parMatrix, h.parRhs, h.parSolution)) ||
      !ok(HYPRE_IJVectorGetValues(h.solution, n, h.rows.data(), z.data()))) {
    fail("BoomerAMG V-cycle", code);
    z = r;
  }
}

}  // namespace tt
