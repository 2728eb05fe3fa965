// Backward Euler with the Cholesky preconditioner: the same steps as with Jacobi (both solved
// tightly) in far fewer iterations; a new factor when the iterations rise above
// refactor_iterations, and only then; a background factor that takes over between steps; and
// a system matrix that is not positive definite, which the factorisation refuses: the matrix
// with the models' PSD-projected stiffness is factored instead (the exact system still solved),
// or, where a force without a projection makes that indefinite too, the rest shape's matrix,
// or, when that is not definite either, the step falls back to Jacobi and still solves, and
// the factor comes once the matrix is definite.
#include <gtest/gtest.h>

#include <memory>

#include "implicit_test_util.h"

namespace tt {
namespace {

using testutil::beam;
using testutil::RunResult;
using testutil::run;
using testutil::Repeller;
using testutil::repelTip;
using testutil::tight;


constexpr auto kJacobiOnly = BackwardEulerParams::Preconditioning::kJacobi;
constexpr auto kCholesky = BackwardEulerParams::Preconditioning::kCholesky;

TEST(BackwardEulerCholesky, TakesTheStepsJacobiTakesInFarFewerIterations) {
  const RunResult jacobi = run(tight(kJacobiOnly), 30);
  const RunResult cholesky = run(tight(kCholesky), 30);  // refactor_iterations 15
  const double travel = (jacobi.x - jacobi.start).lpNorm<Eigen::Infinity>();
  ASSERT_GT(travel, 0.02) << "travel " << travel;  // the beam did deflect (2 cm and more)
  EXPECT_LT((cholesky.x - jacobi.x).lpNorm<Eigen::Infinity>(), 1e-9 * travel);
  EXPECT_GE(cholesky.diagnostics.factorizations, 1);
  EXPECT_EQ(cholesky.diagnostics.jacobiFallbacks, 0);
  EXPECT_EQ(cholesky.diagnostics.unconvergedLinear, 0);
  EXPECT_LT(3 * cholesky.linearIterations, jacobi.linearIterations)
      << "cholesky " << cholesky.linearIterations << ", jacobi " << jacobi.linearIterations;
}

TEST(BackwardEulerCholesky, RefactorsWhenTheIterationsRiseAboveTheThreshold) {
  BackwardEulerParams p = tight(kCholesky);
  p.refactorIterations = 1000;
  const RunResult once = run(p, 30);
  p.refactorIterations = 15;
  const RunResult refactored = run(p, 30);
  EXPECT_EQ(once.diagnostics.factorizations, 1);
  EXPECT_GE(refactored.diagnostics.factorizations, 2);
  // The first factor alone goes stale as the beam swings through large rotations.
  EXPECT_LT(3 * refactored.linearIterations, once.linearIterations)
      << "refactored " << refactored.linearIterations << ", once " << once.linearIterations;
  EXPECT_LT((refactored.x - once.x).lpNorm<Eigen::Infinity>(), 1e-9);
}

TEST(BackwardEulerCholesky, ABackgroundFactorTakesOverBetweenSteps) {
  BackwardEulerParams p = tight(kCholesky);
  p.refactorIterations = 6;
  p.backgroundRefactor = true;
  const RunResult background = run(p, 60);
  p.backgroundRefactor = false;
  const RunResult synchronous = run(p, 60);
  EXPECT_GE(background.diagnostics.factorizations, 2);
  EXPECT_LT((background.x - synchronous.x).lpNorm<Eigen::Infinity>(), 1e-10);
}

TEST(BackwardEulerCholesky, AMatrixThatIsNotPositiveDefiniteFallsBackToJacobi) {
  auto s = beam();
  Repeller& r = repelTip(*s);
  const double h = 0.02;
  BackwardEulerParams p = tight(kCholesky);
  p.refactorIterations = 1;
  BackwardEulerIntegrator be(p);

  const StepReport first = be.advance(*s, h);
  EXPECT_TRUE(first.ok) << first.failure;
  EXPECT_TRUE(s->state.x.allFinite());
  EXPECT_EQ(be.diagnostics().factorizations, 0);
  // This step's matrix, its projection (the repeller has none) and the rest shape's.
  EXPECT_EQ(be.diagnostics().notPositiveDefinite, 3);
  EXPECT_NE(be.diagnostics().lastRefusal.find("not positive definite"), std::string::npos)
      << be.diagnostics().lastRefusal;
  EXPECT_GE(be.diagnostics().jacobiFallbacks, 1);
  EXPECT_LT(be.diagnostics().lastRelativeResidual, 1e-10);  // solved all the same (BiCGSTAB)

  r.k = 0.0;  // definite again: a factor comes once the retry wait is over
  for (int i = 0; i < 12; ++i) EXPECT_TRUE(be.advance(*s, h).ok);
  EXPECT_EQ(be.diagnostics().notPositiveDefinite, 3);
  EXPECT_GE(be.diagnostics().factorizations, 1);
}

TEST(BackwardEulerCholesky, AnIndefiniteMatrixAwayFromRestIsPreconditionedByTheRestShapesFactor) {
  auto s = beam();
  const int tip = s->numNodes() - 1;
  const Eigen::Vector3d rest = s->mesh.rest.col(tip);
  auto repeller = std::make_unique<Repeller>(tip, rest + Eigen::Vector3d(0, 0, 0.01), rest);
  Repeller& r = *repeller;
  r.awayFromRestOnly = true;
  s->models.push_back(std::move(repeller));
  const double h = 0.02;
  BackwardEulerIntegrator jacobiOnly(tight(kJacobiOnly));
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(jacobiOnly.advance(*s, h).ok);  // away from rest
  SparseMatrix K;
  s->assembleStiffness(s->state.x, K);
  r.k = 10.0 * (-K.diagonal().segment<3>(3 * tip)).maxCoeff();

  BackwardEulerIntegrator be(tight(kCholesky));
  const StepReport step = be.advance(*s, h);
  EXPECT_TRUE(step.ok) << step.failure;
  EXPECT_EQ(be.diagnostics().notPositiveDefinite, 2);  // this step's matrix and its projection
  EXPECT_EQ(be.diagnostics().factorizations, 1);       // the rest shape's
  EXPECT_EQ(be.diagnostics().jacobiFallbacks, 0);
  EXPECT_LT(be.diagnostics().lastRelativeResidual, 1e-10);
}

// The beam squeezed to 90 % of its length: the StVK stiffness is indefinite there (compressive
// stress in its geometric term) and, with a long step, so is the system matrix. The factor of
// the PSD-projected matrix preconditions the exact system (BiCGSTAB once CG meets negative
// curvature), whose step is the one Jacobi takes. (On this beam the rest shape's factor, the
// fallback before, took 125 iterations where this one takes 60, Jacobi 44.)
TEST(BackwardEulerCholesky, ACompressedTissuesStepIsPreconditionedByItsProjectedFactor) {
  auto squeezed = [] {
    auto s = beam();
    for (int n = 0; n < s->numNodes(); ++n) {
      s->state.x[3 * n] = 0.9 * s->mesh.rest(0, n);  // the beam lies along x, clamped at x = 0
      s->state.v.segment<3>(3 * n).setZero();
    }
    return s;
  };
  const double h = 0.1;
  auto exact = squeezed();
  const Eigen::VectorXd start = exact->state.x;
  BackwardEulerIntegrator jacobi(tight(kJacobiOnly));
  ASSERT_TRUE(jacobi.advance(*exact, h).ok);
  ASSERT_LT(jacobi.diagnostics().lastRelativeResidual, 1e-10);

  auto s = squeezed();
  BackwardEulerParams p = tight(kCholesky);
  p.refactorIterations = 1000;
  BackwardEulerIntegrator be(p);
  const StepReport step = be.advance(*s, h);
  EXPECT_TRUE(step.ok) << step.failure;
  ASSERT_EQ(be.diagnostics().notPositiveDefinite, 1) << "the step's matrix should be indefinite";
  EXPECT_EQ(be.diagnostics().projectedFactors, 1);
  EXPECT_EQ(be.diagnostics().factorizations, 1);
  EXPECT_EQ(be.diagnostics().jacobiFallbacks, 0);
  EXPECT_EQ(be.diagnostics().unconvergedLinear, 0);
  EXPECT_LT(be.diagnostics().lastRelativeResidual, 1e-10);
  const double travel = (exact->state.x - start).lpNorm<Eigen::Infinity>();
  ASSERT_GT(travel, 1e-4);
  EXPECT_LT((s->state.x - exact->state.x).lpNorm<Eigen::Infinity>(), 1e-8 * travel);
}

}  // namespace
}  // namespace tt
