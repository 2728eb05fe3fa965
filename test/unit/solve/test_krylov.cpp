// The Krylov solvers of solve/krylov.h on problems with known properties: the 2-D Poisson
// matrix (symmetric positive definite), a badly scaled copy of it (what Jacobi is for), an
// indefinite matrix (CG must say so), and a convection-diffusion matrix (non-symmetric:
// BiCGSTAB and GMRES). Every answer is checked by its true residual, not the solver's own.
#include <gtest/gtest.h>

#include <vector>

#include "solve_test_util.h"
#include "tissue_trainer/core/solve/krylov.h"

namespace tt {
namespace {

// (n x n grid) 5-point Laplacian + shift * I, with convection `wind` (non-symmetric if != 0).
SparseMatrix gridMatrix(int n, double shift, double wind = 0.0) {
  std::vector<Eigen::Triplet<double>> t;
  const auto id = [n](int i, int j) { return i + n * j; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      t.emplace_back(id(i, j), id(i, j), 4.0 + shift);
      if (i > 0) t.emplace_back(id(i, j), id(i - 1, j), -1.0 - wind);
      if (i + 1 < n) t.emplace_back(id(i, j), id(i + 1, j), -1.0 + wind);
      if (j > 0) t.emplace_back(id(i, j), id(i, j - 1), -1.0);
      if (j + 1 < n) t.emplace_back(id(i, j), id(i, j + 1), -1.0);
    }
  SparseMatrix A(n * n, n * n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

double trueResidual(const SparseMatrix& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  return (b - A * x).norm() / b.norm();
}

// A matrix-free operator: the same matrix, applied through a callable.
class CallableOperator final : public LinearOperator {
 public:
  explicit CallableOperator(const SparseMatrix& A) : A_(A) {}
  Eigen::Index size() const override { return A_.rows(); }
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override {
    y.setZero(x.size());
    for (int row = 0; row < A_.outerSize(); ++row)
      for (SparseMatrix::InnerIterator it(A_, row); it; ++it) y[row] += it.value() * x[it.col()];
  }

 private:
  const SparseMatrix& A_;
};

TEST(Krylov, ConjugateGradientsSolvesTheSpdProblem) {
  const SparseMatrix A = gridMatrix(20, 0.01);
  const Eigen::VectorXd b = randomVector(A.rows(), 1);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  KrylovWorkspace work;
  const SolveReport r = conjugateGradients(MatrixOperator(A), b, x, IdentityPreconditioner(),
                                           {1e-10, 1000, 30}, work);
  EXPECT_TRUE(r.converged()) << outcomeName(r.outcome);
  EXPECT_LT(trueResidual(A, b, x), 2e-10);
  EXPECT_NEAR(r.relativeResidual, trueResidual(A, b, x), 1e-11);
  EXPECT_LT(r.iterations, A.rows());

  // Matrix-free: the same iterates.
  Eigen::VectorXd y = Eigen::VectorXd::Zero(A.rows());
  const SolveReport free = conjugateGradients(CallableOperator(A), b, y, IdentityPreconditioner(),
                                              {1e-10, 1000, 30}, work);
  EXPECT_EQ(free.iterations, r.iterations);
  EXPECT_LT((x - y).norm(), 1e-12 * x.norm());

  // Warm-started at the answer: nothing to do.
  const SolveReport again = conjugateGradients(MatrixOperator(A), b, x, IdentityPreconditioner(),
                                               {1e-9, 1000, 30}, work);
  EXPECT_EQ(again.iterations, 0);
}

TEST(Krylov, JacobiPreconditioningPaysOnABadlyScaledMatrix) {
  SparseMatrix A = gridMatrix(20, 0.01);
  Eigen::VectorXd d(A.rows());
  for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = std::pow(10.0, 3.0 * i / d.size());
  A = d.asDiagonal() * A * d.asDiagonal();
  const Eigen::VectorXd b = randomVector(A.rows(), 2);
  KrylovWorkspace work;
  JacobiPreconditioner jacobi;
  ASSERT_TRUE(jacobi.setFromMatrix(A));
  EXPECT_TRUE(jacobi.positive());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows()), y = x;
  const SolveReport plain =
      conjugateGradients(MatrixOperator(A), b, x, IdentityPreconditioner(), {1e-8, 5000, 30}, work);
  const SolveReport pcg = conjugateGradients(MatrixOperator(A), b, y, jacobi, {1e-8, 5000, 30}, work);
  ASSERT_TRUE(pcg.converged());
  EXPECT_LT(trueResidual(A, b, y), 1e-7);
  EXPECT_LT(2 * pcg.iterations, plain.iterations)
      << "Jacobi " << pcg.iterations << " vs plain " << plain.iterations;
}

TEST(Krylov, ConjugateGradientsReportsAnIndefiniteMatrix) {
  const SparseMatrix A = gridMatrix(10, -3.0);  // eigenvalues on both sides of zero
  const Eigen::VectorXd b = randomVector(A.rows(), 3);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  KrylovWorkspace work;
  const SolveReport r = conjugateGradients(MatrixOperator(A), b, x, IdentityPreconditioner(),
                                           {1e-10, 1000, 30}, work);
  EXPECT_EQ(r.outcome, SolveOutcome::kNonPositiveCurvature);
  JacobiPreconditioner jacobi;
  jacobi.setFromMatrix(gridMatrix(10, -5.0));
  EXPECT_FALSE(jacobi.positive());
}

TEST(Krylov, BiCgStabAndGmresSolveANonSymmetricProblem) {
  const SparseMatrix A = gridMatrix(20, 0.1, 0.6);
  ASSERT_GT((Eigen::MatrixXd(A) - Eigen::MatrixXd(A).transpose()).norm(), 1.0);
  const Eigen::VectorXd b = randomVector(A.rows(), 4);
  KrylovWorkspace work;
  JacobiPreconditioner jacobi;
  jacobi.setFromMatrix(A);
  for (const Preconditioner* M :
       {static_cast<const Preconditioner*>(&jacobi), static_cast<const Preconditioner*>(nullptr)}) {
    const IdentityPreconditioner identity;
    const Preconditioner& P = M ? *M : identity;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
    const SolveReport s = biCgStab(MatrixOperator(A), b, x, P, {1e-10, 2000, 30}, work);
    EXPECT_TRUE(s.converged()) << outcomeName(s.outcome);
    EXPECT_LT(trueResidual(A, b, x), 2e-10);
    for (int restart : {30, 5}) {
      Eigen::VectorXd y = Eigen::VectorXd::Zero(A.rows());
      const SolveReport g = gmres(MatrixOperator(A), b, y, P, {1e-10, 4000, restart}, work);
      EXPECT_TRUE(g.converged()) << "GMRES(" << restart << "): " << outcomeName(g.outcome);
      EXPECT_LT(trueResidual(A, b, y), 2e-10) << "GMRES(" << restart << ")";
      EXPECT_NEAR(g.relativeResidual, trueResidual(A, b, y), 1e-10);
    }
  }
}

TEST(Krylov, IterationLimitAndZeroRightSide) {
  const SparseMatrix A = gridMatrix(20, 0.01, 0.3);
  const Eigen::VectorXd b = randomVector(A.rows(), 5);
  KrylovWorkspace work;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  const SolveReport g = gmres(MatrixOperator(A), b, x, IdentityPreconditioner(), {1e-12, 3, 30}, work);
  EXPECT_EQ(g.outcome, SolveOutcome::kMaxIterations);
  EXPECT_EQ(g.iterations, 3);
  EXPECT_GT(trueResidual(A, b, x), 1e-3);
  x = randomVector(A.rows(), 6);
  const SolveReport z = biCgStab(MatrixOperator(A), Eigen::VectorXd::Zero(A.rows()), x,
                                 IdentityPreconditioner(), {1e-12, 100, 30}, work);
  EXPECT_TRUE(z.converged());
  EXPECT_EQ(x.norm(), 0.0);
}

}  // namespace
}  // namespace tt
