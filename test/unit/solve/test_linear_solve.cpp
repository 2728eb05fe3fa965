// The rule of solve/linear_solve.h on small matrices: Jacobi while no factor serves, a new
// factor after a slow solve (later, or at once under the Newton rule), the fallbacks and the
// retry wait after a refused factorisation, and the curvature fallback.
#include <gtest/gtest.h>

#include <vector>

#include "solve_test_util.h"
#include "tissue_trainer/core/solve/linear_solve.h"

namespace tt {
namespace {

// The 1-D Laplacian (Dirichlet ends) plus `shift` on the diagonal, with the diagonal scaled by
// 1 + row / n so that Jacobi is not exact: symmetric positive definite for shift > -small.
SparseMatrix laplacianPlus(int n, double shift, double stiffness = 1.0) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, stiffness * (2.0 + shift) * (1.0 + double(i) / n));
    if (i > 0) t.emplace_back(i, i - 1, -stiffness);
    if (i + 1 < n) t.emplace_back(i, i + 1, -stiffness);
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

constexpr int kSize = 60;

LinearSolveSettings choleskyAtOnce(int refactorIterations) {
  LinearSolveSettings s;
  s.preconditioner = PreconditionerKind::kCholesky;
  s.backgroundRefactor = false;
  s.refactorIterations = refactorIterations;
  s.tolerance = 1e-10;
  s.maxIterations = 1000;
  return s;
}

double relativeResidualOf(const SparseMatrix& A, const Eigen::VectorXd& b,
                          const Eigen::VectorXd& x) {
  return (b - A * x).norm() / b.norm();
}

// Fallback matrices that count how often they were asked for.
class CountingFallbacks final : public FactorFallbacks {
 public:
  CountingFallbacks(bool projectable, SparseMatrix projected, SparseMatrix rest)
      : projectable_(projectable), projected_(std::move(projected)), rest_(std::move(rest)) {}
  bool canProject() const override { return projectable_; }
  const SparseMatrix& projectedMatrix() override {
    ++projectedAsked;
    return projected_;
  }
  const SparseMatrix& restMatrix() override {
    ++restAsked;
    return rest_;
  }
  int projectedAsked = 0, restAsked = 0;

 private:
  bool projectable_;
  SparseMatrix projected_, rest_;
};

TEST(LinearSolve, JacobiPreconditionsWhileNoFactorServes) {
  const SparseMatrix A = laplacianPlus(kSize, 0.01);
  const SparseMatrix refused = -laplacianPlus(kSize, 0.01);
  const Eigen::VectorXd b = randomVector(kSize, 1);
  LinearSolve solve(choleskyAtOnce(100000));  // never slow enough for a new factor
  solve.ensureFactor(refused);                // not positive definite: no factor
  ASSERT_EQ(solve.diagnostics().notPositiveDefinite, 1);
  ASSERT_EQ(solve.factor(kSize), nullptr);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(kSize);
  const LinearSolveReport first = solve.solve(A, b, x);
  // The same solve by hand with Jacobi: the same iterations.
  JacobiPreconditioner jacobi;
  jacobi.setFromMatrix(A);
  KrylovWorkspace work;
  Eigen::VectorXd y = Eigen::VectorXd::Zero(kSize);
  const SolveReport byHand =
      conjugateGradients(MatrixOperator(A), b, y, jacobi, {1e-10, 1000, 30}, work);
  EXPECT_EQ(first.iterations, byHand.iterations);
  EXPECT_GT(first.iterations, 10);
  EXPECT_EQ(solve.diagnostics().jacobiFallbacks, 1);
  EXPECT_EQ(solve.diagnostics().factorizations, 0);
  EXPECT_LT(relativeResidualOf(A, b, x), 1e-9);

  LinearSolve factored(choleskyAtOnce(100000));
  factored.ensureFactor(A);
  EXPECT_EQ(factored.diagnostics().factorizations, 1);
  x.setZero();
  EXPECT_LE(factored.solve(A, b, x).iterations, 2);
  EXPECT_EQ(factored.diagnostics().jacobiFallbacks, 0) << "no fallback once a factor serves";
}

TEST(LinearSolve, ASlowSolveStartsANewFactorForTheNextSolves) {
  const SparseMatrix A1 = laplacianPlus(kSize, 0.01);
  const SparseMatrix A2 = laplacianPlus(kSize, 0.3, 4.0);  // a stiffer neighbour
  const Eigen::VectorXd b = randomVector(kSize, 2);
  for (const int threshold : {1, 1000}) {
    LinearSolve solve(choleskyAtOnce(threshold));
    solve.ensureFactor(A1);
    ASSERT_EQ(solve.diagnostics().factorizations, 1);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(kSize);
    const int stale = solve.solve(A2, b, x).iterations;
    EXPECT_GT(stale, 2) << "A1's factor is only an approximation of A2";
    EXPECT_LT(relativeResidualOf(A2, b, x), 1e-9) << "the slow answer is kept";
    const bool slow = stale > threshold;
    EXPECT_EQ(solve.diagnostics().factorizations, slow ? 2 : 1) << threshold;
    x.setZero();
    const int next = solve.solve(A2, b, x).iterations;
    if (slow)
      EXPECT_LE(next, 2) << "the new factor is A2's";
    else
      EXPECT_EQ(next, stale) << "A1's factor is kept";
  }
}

TEST(LinearSolve, NewtonRuleCutsTheKeptFactorsTryAndSolvesAgainWithANewOne) {
  const SparseMatrix A1 = laplacianPlus(kSize, 0.01);
  const SparseMatrix A2 = laplacianPlus(kSize, 0.3, 4.0);
  const Eigen::VectorXd b = randomVector(kSize, 3);
  LinearSolve solve(choleskyAtOnce(1), LinearSolveRule::newtonDirections());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(kSize);
  const LinearSolveReport first = solve.solve(A1, b, x);  // no factor yet: one of A1
  EXPECT_EQ(solve.diagnostics().factorizations, 1);
  EXPECT_LE(first.iterations, 2);
  x.setZero();
  const LinearSolveReport second = solve.solve(A2, b, x);
  EXPECT_EQ(solve.diagnostics().factorizations, 2);
  // One iteration with A1's factor (cut at refactorIterations), then A2's own.
  EXPECT_GE(second.iterations, 2);
  EXPECT_LE(second.iterations, 3);
  EXPECT_TRUE(second.converged());
  EXPECT_LT(relativeResidualOf(A2, b, x), 1e-9);

  // 0: a new factor for every solve, even of the same matrix.
  LinearSolve everySolve(choleskyAtOnce(0), LinearSolveRule::newtonDirections());
  for (int k = 1; k <= 3; ++k) {
    x.setZero();
    everySolve.solve(A1, b, x);
    EXPECT_EQ(everySolve.diagnostics().factorizations, k);
  }
}

TEST(LinearSolve, ARefusedFactorFallsBackToTheProjectedThenTheRestMatrix) {
  const SparseMatrix negativeDefinite = SparseMatrix(-laplacianPlus(kSize, 0.01));
  const SparseMatrix projected = laplacianPlus(kSize, 0.02);
  const SparseMatrix rest = laplacianPlus(kSize, 0.05);
  {
    CountingFallbacks fallbacks(true, projected, rest);
    LinearSolve solve(choleskyAtOnce(15));
    solve.ensureFactor(negativeDefinite, &fallbacks);
    EXPECT_EQ(solve.diagnostics().notPositiveDefinite, 1);
    EXPECT_EQ(solve.diagnostics().factorizations, 1);
    EXPECT_EQ(solve.diagnostics().projectedFactors, 1);
    EXPECT_EQ(fallbacks.projectedAsked, 1);
    EXPECT_EQ(fallbacks.restAsked, 0);
    ASSERT_NE(solve.factor(kSize), nullptr);
  }
  {
    CountingFallbacks fallbacks(false, projected, rest);
    LinearSolve solve(choleskyAtOnce(15));
    solve.ensureFactor(negativeDefinite, &fallbacks);
    EXPECT_EQ(solve.diagnostics().notPositiveDefinite, 1);
    EXPECT_EQ(solve.diagnostics().factorizations, 1);
    EXPECT_EQ(fallbacks.projectedAsked, 0);
    EXPECT_EQ(fallbacks.restAsked, 1);
  }
  {  // Newton rule, no fallbacks: the caller is told, and nothing is solved.
    LinearSolve solve(choleskyAtOnce(15), LinearSolveRule::newtonDirections());
    const Eigen::VectorXd b = randomVector(kSize, 4);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(kSize);
    const LinearSolveReport report = solve.solve(negativeDefinite, b, x);
    EXPECT_TRUE(report.refused);
    EXPECT_FALSE(report.converged());
    EXPECT_EQ(report.iterations, 0);
    EXPECT_EQ(x.lpNorm<Eigen::Infinity>(), 0.0);
    EXPECT_EQ(solve.factor(kSize), nullptr);
  }
}

TEST(LinearSolve, ARefusalWaitsItsSolvesBeforeTheNextTry) {
  const SparseMatrix negativeDefinite = SparseMatrix(-laplacianPlus(kSize, 0.01));
  const Eigen::VectorXd b = randomVector(kSize, 5);
  const LinearSolveRule rule = LinearSolveRule::timeStepping();
  ASSERT_GT(rule.retryAfterRefusal, 0);
  LinearSolve solve(choleskyAtOnce(15), rule);
  solve.ensureFactor(negativeDefinite);
  EXPECT_EQ(solve.diagnostics().notPositiveDefinite, 1);
  for (int k = 0; k < rule.retryAfterRefusal; ++k) {
    solve.ensureFactor(negativeDefinite);
    EXPECT_EQ(solve.diagnostics().notPositiveDefinite, 1) << "tried again after " << k;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(kSize);
    const LinearSolveReport report = solve.solve(negativeDefinite, b, x);
    // Jacobi meets the negativeDefinite matrix (a negative diagonal): BiCGSTAB solves it.
    EXPECT_TRUE(report.lostCurvature);
    EXPECT_LT(relativeResidualOf(negativeDefinite, b, x), 1e-8);
  }
  EXPECT_EQ(solve.diagnostics().jacobiFallbacks, rule.retryAfterRefusal);
  EXPECT_EQ(solve.diagnostics().nonPositiveCurvature, rule.retryAfterRefusal);
  solve.ensureFactor(negativeDefinite);
  EXPECT_EQ(solve.diagnostics().notPositiveDefinite, 2) << "tried again once the wait is over";
}

TEST(LinearSolve, NewtonRuleReportsNonPositiveCurvatureInsteadOfBiCgStab) {
  const SparseMatrix negativeDefinite = SparseMatrix(-laplacianPlus(kSize, 0.01));
  const Eigen::VectorXd b = randomVector(kSize, 6);
  LinearSolveSettings jacobi;
  jacobi.preconditioner = PreconditionerKind::kJacobi;
  LinearSolve newton(jacobi, LinearSolveRule::newtonDirections());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(kSize);
  const LinearSolveReport report = newton.solve(negativeDefinite, b, x);
  EXPECT_TRUE(report.lostCurvature);
  EXPECT_EQ(report.outcome, SolveOutcome::kNonPositiveCurvature);
  EXPECT_EQ(newton.diagnostics().nonPositiveCurvature, 1);
}

}  // namespace
}  // namespace tt
