// Backward Euler with the AMG preconditioner (preconditioner: amg): the steps Jacobi takes
// (both solved tightly) in far fewer iterations; a new hierarchy when the iterations rise
// above refactor_iterations, and only then; an indefinite matrix, where CG with the V-cycle
// meets non-positive curvature and BiCGSTAB still solves; a hypre error, after which the
// solves go on with Jacobi; and the scene key, whose unknown values are one clear error.
#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <string>

#include "implicit_test_util.h"
#include "tissue_trainer/core/scene/registry.h"

namespace tt {
namespace {

using testutil::beam;
using testutil::Repeller;
using testutil::tight;

constexpr auto kJacobi = BackwardEulerParams::Preconditioning::kJacobi;
constexpr auto kAmg = BackwardEulerParams::Preconditioning::kAmg;

struct RunResult {
  Eigen::VectorXd x, start;
  int linearIterations = 0;
  int slowSolves = 0;  // solves above refactorIterations or meeting non-positive curvature
  BackwardEulerDiagnostics diagnostics;
};

// The thrown beam, `cells` cells along and a quarter of them across, one solve per frame.
RunResult run(BackwardEulerParams p, int frames, int cells = 8) {
  auto s = beam(cells, cells / 4);
  RunResult out;
  out.start = s->state.x;
  BackwardEulerIntegrator be(p);
  for (int i = 0; i < frames; ++i) {
    const int curvatureBefore = be.diagnostics().nonPositiveCurvature;
    const StepReport r = be.advance(*s, 0.02);
    EXPECT_TRUE(r.ok) << r.failure;
    out.linearIterations += r.linearIterations;
    if (r.linearIterations > p.refactorIterations ||
        be.diagnostics().nonPositiveCurvature > curvatureBefore)
      ++out.slowSolves;
  }
  out.x = s->state.x;
  out.diagnostics = be.diagnostics();
  return out;
}

TEST(BackwardEulerAmg, TakesTheStepsJacobiTakesInFarFewerIterations) {
  // 16 x 4 x 4 cells: Jacobi needs about 200 iterations a step at 1e-12.
  const RunResult jacobi = run(tight(kJacobi), 30, 16);
  const RunResult amg = run(tight(kAmg), 30, 16);
  const double travel = (jacobi.x - jacobi.start).lpNorm<Eigen::Infinity>();
  ASSERT_GT(travel, 0.02) << "travel " << travel;
  // Both solved to 1e-12; 30 steps (four of them through BiCGSTAB) spread that to ~1e-9.
  EXPECT_LT((amg.x - jacobi.x).lpNorm<Eigen::Infinity>(), 1e-8 * travel);
  EXPECT_GE(amg.diagnostics.factorizations, 1);
  EXPECT_EQ(amg.diagnostics.amgFailures, 0) << amg.diagnostics.amgError;
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
  const int tip = s->numNodes() - 1;
  auto repeller = std::make_unique<Repeller>(tip, s->state.x.segment<3>(3 * tip) + Eigen::Vector3d(0, 0, 0.01));
  Repeller& r = *repeller;
  s->models.push_back(std::move(repeller));
  SparseMatrix K;
  s->assembleStiffness(s->state.x, K);
  r.k = 10.0 * (-K.diagonal().segment<3>(3 * tip)).maxCoeff();  // M - h^2 K indefinite
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
  EXPECT_NE(failed.diagnostics.amgError.find("hypre BoomerAMG configuration failed"),
            std::string::npos) << failed.diagnostics.amgError;
  EXPECT_LT((failed.x - jacobi.x).lpNorm<Eigen::Infinity>(), 1e-9);
}

std::string thrownMessage(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(BackwardEulerAmg, TheSceneKeySelectsItAndATypoNamesTheAcceptedValues) {
  const std::string file = "inline.yaml";
  const YAML::Node amg = YAML::Load("{type: backward_euler, preconditioner: amg}");
  const auto integrator = registry().makeIntegrator(YamlEntry(amg, "integrator", &file));
  const auto* be = dynamic_cast<const BackwardEulerIntegrator*>(integrator.get());
  ASSERT_NE(be, nullptr);
  EXPECT_EQ(be->params.preconditioner, kAmg);

  const YAML::Node typo = YAML::Load("{type: backward_euler, preconditioner: amgg}");
  const std::string message =
      thrownMessage([&] { registry().makeIntegrator(YamlEntry(typo, "integrator", &file)); });
  EXPECT_NE(message.find("integrator.preconditioner: expected one of: jacobi, cholesky, amg"),
            std::string::npos) << message;
  EXPECT_NE(message.find("amgg"), std::string::npos) << message;
}

}  // namespace
}  // namespace tt
