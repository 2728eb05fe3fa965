// Backward Euler with the AMG preconditioner (preconditioner: amg): the steps Jacobi takes
// (both solved tightly) in far fewer iterations; a new hierarchy when the iterations rise
// above refactor_iterations, and only then; an indefinite matrix, where CG with the V-cycle
// meets non-positive curvature and BiCGSTAB still solves; a hypre error, after which the
// solves go on with Jacobi. The scene key is tested with the registry.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "implicit_test_util.h"

namespace tt {
namespace {

using testutil::beam;
using testutil::RunResult;
using testutil::run;
using testutil::repelTip;
using testutil::tight;

constexpr auto kJacobi = BackwardEulerParams::Preconditioning::kJacobi;
constexpr auto kAmg = BackwardEulerParams::Preconditioning::kAmg;

TEST(BackwardEulerAmg, TakesTheStepsJacobiTakesInFarFewerIterations) {
  // 16 x 4 x 4 cells: Jacobi needs about 200 iterations a step at 1e-12.
  const RunResult jacobi = run(tight(kJacobi), 30, 16);
  const RunResult amg = run(tight(kAmg), 30, 16);
  const double travel = (jacobi.x - jacobi.start).lpNorm<Eigen::Infinity>();
  ASSERT_GT(travel, 0.02) << "travel " << travel;
  // Both solved to 1e-12; 30 steps (four of them through BiCGSTAB) spread that to ~1e-9.
  EXPECT_LT((amg.x - jacobi.x).lpNorm<Eigen::Infinity>(), 1e-8 * travel);
  EXPECT_GE(amg.diagnostics.factorizations, 1);
  EXPECT_EQ(amg.diagnostics.amgFailures, 0) << amg.diagnostics.lastRefusal;
  EXPECT_EQ(amg.diagnostics.jacobiFallbacks, 0);
  EXPECT_EQ(amg.diagnostics.unconvergedLinear, 0);
  EXPECT_LT(3 * amg.linearIterations, jacobi.linearIterations)
      << "amg " << amg.linearIterations << ", jacobi " << jacobi.linearIterations;
}

// The Cholesky factor's rule: the first solve's hierarchy, and a new one after every solve
// that needs more than refactor_iterations or meets non-positive curvature.
TEST(BackwardEulerAmg, SetsUpAgainAfterEverySlowSolveAndOnlyThen) {
  BackwardEulerParams p = tight(kAmg);
  p.refactorIterations = 1000;
  const RunResult once = run(p, 30);
  p.refactorIterations = 25;  // between a fresh hierarchy's count (~18) and a stale one's
  const RunResult some = run(p, 30);
  EXPECT_EQ(once.diagnostics.factorizations, 1 + once.slowSolves);
  EXPECT_LE(once.slowSolves, 2);
  EXPECT_EQ(some.diagnostics.factorizations, 1 + some.slowSolves);
  EXPECT_GE(some.slowSolves, 3);
  EXPECT_LT(some.slowSolves, 30);
  EXPECT_LT((some.x - once.x).lpNorm<Eigen::Infinity>(), 1e-9);
}

TEST(BackwardEulerAmg, AnIndefiniteMatrixIsSolvedByBiCgStabWithTheVCycle) {
  auto s = beam();
  repelTip(*s);
  BackwardEulerIntegrator be(tight(kAmg));
  const StepReport step = be.advance(*s, 0.02);
  EXPECT_TRUE(step.ok) << step.failure;
  EXPECT_TRUE(s->state.x.allFinite());
  EXPECT_GE(be.diagnostics().nonPositiveCurvature, 1);
  EXPECT_GE(be.diagnostics().factorizations, 1);  // an indefinite matrix is not refused
  EXPECT_EQ(be.diagnostics().jacobiFallbacks, 0);
  EXPECT_EQ(be.diagnostics().amgFailures, 0);
  EXPECT_LT(be.diagnostics().lastRelativeResidual, 1e-10);
}

TEST(BackwardEulerAmg, AHypreErrorFallsBackToJacobiAndSaysWhy) {
  BackwardEulerParams p = tight(kAmg);
  p.amg.numFunctions = 0;  // hypre rejects the argument at every set-up
  const RunResult failed = run(p, 3);
  const RunResult jacobi = run(tight(kJacobi), 3);
  EXPECT_GE(failed.diagnostics.amgFailures, 1);
  EXPECT_EQ(failed.diagnostics.factorizations, 0);
  EXPECT_EQ(failed.diagnostics.jacobiFallbacks, 3);
  EXPECT_NE(failed.diagnostics.lastRefusal.find("hypre BoomerAMG configuration failed"),
            std::string::npos) << failed.diagnostics.lastRefusal;
  EXPECT_LT((failed.x - jacobi.x).lpNorm<Eigen::Infinity>(), 1e-9);
}

}  // namespace
}  // namespace tt
