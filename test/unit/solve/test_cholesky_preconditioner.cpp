// The sparse Cholesky preconditioner of solve/cholesky_preconditioner.h, both backends: the
// factor of A itself makes CG converge at once, the factor of a nearby matrix in a few
// iterations where Jacobi needs many; a matrix that is not positive definite is refused and
// the previous factor stays; a background factorisation works on its own copy of the matrix
// and takes over only when update() or wait() installs it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "solve_test_util.h"
#include "tissue_trainer/core/solve/cholesky_preconditioner.h"

namespace tt {
namespace {

// (n x n grid) 5-point Laplacian + shift * I, scaled symmetrically to D A D with D's entries
// spread geometrically over [1, spread] (what the element sizes of a mesh do): positive
// definite for shift > 0, indefinite for shift < -0.1.
SparseMatrix scaledGrid(int n, double shift, double spread) {
  std::vector<Eigen::Triplet<double>> t;
  const auto id = [n](int i, int j) { return i + n * j; };
  const auto scale = [n, spread](int k) { return std::pow(spread, double(k) / (n * n)); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int k = id(i, j);
      const auto add = [&](int l, double value) {
        t.emplace_back(k, l, scale(k) * value * scale(l));
      };
      add(k, 4.0 + shift);
      if (i > 0) add(id(i - 1, j), -1.0);
      if (i + 1 < n) add(id(i + 1, j), -1.0);
      if (j > 0) add(id(i, j - 1), -1.0);
      if (j + 1 < n) add(id(i, j + 1), -1.0);
    }
  SparseMatrix A(n * n, n * n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

// CG on A from zero with preconditioner M; the true relative residual must meet 1e-10.
int cgIterations(const SparseMatrix& A, const Preconditioner& M) {
  const Eigen::VectorXd b = randomVector(A.rows(), 7);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  KrylovWorkspace work;
  const SolveReport r = conjugateGradients(MatrixOperator(A), b, x, M, {1e-10, 2000, 30}, work);
  EXPECT_TRUE(r.converged()) << outcomeName(r.outcome);
  EXPECT_LT((b - A * x).norm() / b.norm(), 2e-10);
  return r.iterations;
}

class CholeskyBackends : public ::testing::TestWithParam<CholeskyBackend> {};

TEST_P(CholeskyBackends, TheFactorOfAItselfSolvesInOneIteration) {
  const SparseMatrix A = scaledGrid(30, 0.05, 1e3);
  CholeskyPreconditioner M(false, GetParam());
  EXPECT_FALSE(M.ready());
  ASSERT_TRUE(M.factorNow(A));
  EXPECT_TRUE(M.ready());
  EXPECT_EQ(M.factorizations(), 1);
  EXPECT_LE(cgIterations(A, M), 2);
  const Eigen::VectorXd r = randomVector(A.rows(), 3);
  Eigen::VectorXd z;
  M.apply(r, z);
  EXPECT_LT((A * z - r).norm(), 1e-10 * r.norm());
}

TEST_P(CholeskyBackends, TheFactorOfANearbyMatrixBeatsJacobi) {
  const SparseMatrix old = scaledGrid(30, 0.05, 1e3);
  // A stiffer copy, as the next step's matrix is: + 1 % of the diagonal.
  SparseMatrix A = old;
  for (int row = 0; row < A.rows(); ++row) A.coeffRef(row, row) *= 1.01;
  CholeskyPreconditioner M(false, GetParam());
  ASSERT_TRUE(M.factorNow(old));
  JacobiPreconditioner jacobi;
  ASSERT_TRUE(jacobi.setFromMatrix(A));
  const int withFactor = cgIterations(A, M), withJacobi = cgIterations(A, jacobi);
  EXPECT_LE(withFactor, 15);
  EXPECT_GT(withJacobi, 5 * withFactor);
}

TEST_P(CholeskyBackends, AMatrixThatIsNotPositiveDefiniteIsRefusedAndTheOldFactorStays) {
  const SparseMatrix good = scaledGrid(12, 0.05, 10.0);
  const SparseMatrix indefinite = scaledGrid(12, -3.0, 10.0);  // eigenvalues either side of 0
  CholeskyPreconditioner M(false, GetParam());
  EXPECT_FALSE(M.factorNow(indefinite));
  EXPECT_FALSE(M.ready());
  EXPECT_EQ(M.notPositiveDefinite(), 1);
  const Eigen::VectorXd r = randomVector(good.rows(), 5);
  Eigen::VectorXd z;
  M.apply(r, z);  // no factor: the identity
  EXPECT_EQ(z, r);

  ASSERT_TRUE(M.factorNow(good));
  EXPECT_FALSE(M.refactor(indefinite));  // synchronous: refused at once
  EXPECT_EQ(M.notPositiveDefinite(), 2);
  EXPECT_TRUE(M.ready());
  M.apply(r, z);
  EXPECT_LT((good * z - r).norm(), 1e-10 * r.norm());  // still the factor of `good`
}

TEST_P(CholeskyBackends, ABackgroundFactorTakesOverOnlyWhenInstalled) {
  const SparseMatrix first = scaledGrid(40, 0.05, 1e2);
  SparseMatrix second = 2.0 * first;
  CholeskyPreconditioner M(true, GetParam());
  ASSERT_TRUE(M.factorNow(first));
  ASSERT_TRUE(M.refactor(second));
  EXPECT_TRUE(M.busy());
  EXPECT_FALSE(M.refactor(first));  // one at a time
  second *= 10.0;                   // the factorisation works on its own copy
  const Eigen::VectorXd r = randomVector(first.rows(), 9);
  Eigen::VectorXd z;
  M.apply(r, z);  // until installed, the first factor serves
  EXPECT_LT((first * z - r).norm(), 1e-10 * r.norm());
  EXPECT_TRUE(M.wait());
  EXPECT_FALSE(M.busy());
  EXPECT_EQ(M.factorizations(), 2);
  M.apply(r, z);
  EXPECT_LT((2.0 * first * z - r).norm(), 1e-10 * r.norm());
  EXPECT_FALSE(M.update());  // nothing more to install
}

INSTANTIATE_TEST_SUITE_P(Cholesky, CholeskyBackends,
                         ::testing::Values(CholeskyBackend::kCholmod,
                                           CholeskyBackend::kEigenSimplicial),
                         [](const auto& info) { return std::string(backendName(info.param)); });

}  // namespace
}  // namespace tt
