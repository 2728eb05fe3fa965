// Backward Euler's linear solver choice (PCG, GMRES(m), BiCGSTAB, each with the chosen
// preconditioner) and its iteration-count step control ("Adamss: Advanced Anisotropic
// Mass-Spring System", Sec. 2.5.5): every solver takes PCG's steps; on the thrown cantilever,
// whose iteration count rises with the step, a step whose count reaches the upper limit is
// halved and redone, one at or below the lower limit doubles the next, the steps stay within
// [h_min, h_max] and every frame ends exactly at its end.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "implicit_test_util.h"
#include "tissue_trainer/core/integrate/step_control.h"

namespace tt {
namespace {

using testutil::beam;
using testutil::RunResult;
using testutil::run;
using testutil::tight;
using Preconditioning = BackwardEulerParams::Preconditioning;
using LinearSolver = BackwardEulerParams::LinearSolver;

// Solved to 1e-11: restarted GMRES with short cycles stagnates on this stiff beam with Jacobi
// (GMRES(10) misses 1e-12 in 5000 iterations).
TEST(BackwardEulerSolvers, EverySolverTakesThePcgSteps) {
  for (Preconditioning preconditioner : {Preconditioning::kJacobi, Preconditioning::kCholesky}) {
    BackwardEulerParams p = tight(preconditioner);
    p.linearTolerance = 1e-11;
    const RunResult pcg = run(p, 10);
    const double travel = (pcg.x - pcg.start).lpNorm<Eigen::Infinity>();
    ASSERT_GT(travel, 0.01);
    const std::pair<LinearSolver, int> solvers[] = {
        {LinearSolver::kGmres, 30}, {LinearSolver::kBiCgStab, 30}};
    for (const auto& [solver, restart] : solvers) {
      p.linearSolver = solver;
      p.gmresRestart = restart;
      const RunResult other = run(p, 10);
      const std::string what = "solver " + std::to_string(static_cast<int>(solver)) +
                               ", restart " + std::to_string(restart) + ", preconditioner " +
                               std::to_string(static_cast<int>(preconditioner));
      EXPECT_LT((other.x - pcg.x).lpNorm<Eigen::Infinity>(), 1e-8 * travel) << what;
      EXPECT_EQ(other.diagnostics.unconvergedLinear, 0) << what;
      EXPECT_EQ(other.diagnostics.nonPositiveCurvature, 0) << what << ": no CG to fall back from";
      EXPECT_LT(other.diagnostics.lastRelativeResidual, 1e-11) << what;
    }
  }
}

// GMRES's restart length is the one asked for: a cycle of 2 on this matrix needs far more
// iterations than one of 60.
TEST(BackwardEulerSolvers, GmresRestartLengthIsUsed) {
  BackwardEulerParams p = tight(Preconditioning::kJacobi);
  p.linearSolver = LinearSolver::kGmres;
  p.gmresRestart = 60;
  const RunResult longCycles = run(p, 3);
  p.gmresRestart = 2;
  const RunResult shortCycles = run(p, 3);
  EXPECT_GT(shortCycles.linearIterations, 2 * longCycles.linearIterations)
      << shortCycles.linearIterations << " vs " << longCycles.linearIterations;
}

// What the controller saw of every attempt: its length, the length planned for it (before a
// cut to the frame's end), its iteration count and whether it was kept.
struct Attempt {
  double h, planned;
  int iterations;
  bool kept;
};

class RecordingControl final : public HalvingDoublingControl {
 public:
  explicit RecordingControl(HalvingDoublingParams p) : HalvingDoublingControl(p), max_(p.maxStep) {}
  std::vector<Attempt> attempts;

 protected:
  double afterKeep(double h, const StepMeasure& m, bool last) override {
    attempts.push_back({h, std::min(proposedStep(), max_), m.iterations, true});
    return HalvingDoublingControl::afterKeep(h, m, last);
  }
  double afterReject(double h, const StepMeasure& m) override {
    attempts.push_back({h, std::min(proposedStep(), max_), m.iterations, false});
    return HalvingDoublingControl::afterReject(h, m);
  }

 private:
  double max_;
};

BackwardEulerParams countingParams() {
  BackwardEulerParams p;
  p.preconditioner = BackwardEulerParams::Preconditioning::kJacobi;  // the counts below are Jacobi-PCG's
  p.linearTolerance = 1e-10;
  p.linearMaxIterations = 2000;
  p.warmStart = false;  // the count then depends on the step, not on the previous answer
  return p;
}

// Iterations of one step of length h from the thrown beam's initial state.
int iterationsOfOneStep(double h) {
  auto s = beam();
  BackwardEulerIntegrator be(countingParams());
  const StepReport r = be.advance(*s, h);
  EXPECT_TRUE(r.ok) << r.failure;
  return r.linearIterations;
}

struct ControlRun {
  std::vector<Attempt> attempts;
  int substeps = 0, rejected = 0, halvings = 0, doublings = 0;
};

// Five frames of 0.02 s of the thrown beam from `initialStep`, the controller's rules checked
// on every attempt.
ControlRun runAdaptive(const BackwardEulerParams& p) {
  auto control = std::make_unique<RecordingControl>(iterationStepControl(p));
  RecordingControl& record = *control;
  BackwardEulerIntegrator be(p, std::move(control));
  auto s = beam();
  ControlRun out;
  for (int i = 0; i < 5; ++i) {
    const double end = s->state.t + 0.02;
    const StepReport r = be.advance(*s, 0.02);
    EXPECT_TRUE(r.ok) << r.failure;
    EXPECT_EQ(s->state.t, end) << "the frame ends exactly at its end";
    out.substeps += r.substeps;
    out.rejected += r.rejected;
    EXPECT_FALSE(record.attempts.empty());
    if (!record.attempts.empty()) EXPECT_EQ(r.lastStep, record.attempts.back().h);
  }
  const std::vector<Attempt>& a = out.attempts = record.attempts;
  const double hMin = p.minStep, hMax = p.maxStep;
  int kept = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    const bool cut = a[k].h < a[k].planned * (1.0 - 1e-12);  // the frame's last step
    const bool atMin = a[k].h <= hMin * (1.0 + 1e-9);
    EXPECT_LE(a[k].h, hMax * (1.0 + 1e-12)) << k;
    if (!cut) EXPECT_GE(a[k].h, hMin * (1.0 - 1e-12)) << k;
    if (a[k].kept) ++kept;
    const bool atUpper = a[k].iterations >= p.upperIterations;
    if (!atMin) EXPECT_EQ(a[k].kept, !atUpper) << k << ": " << a[k].iterations << " iterations";
    if (k + 1 == a.size() || cut) continue;
    const double next = a[k + 1].planned;
    if (atUpper && !atMin) {
      EXPECT_DOUBLE_EQ(next, std::max(0.5 * a[k].h, hMin)) << k;
      ++out.halvings;
    } else if (a[k].iterations <= p.lowerIterations) {
      EXPECT_DOUBLE_EQ(next, std::min(2.0 * a[k].h, hMax)) << k;
      if (a[k].h < hMax) ++out.doublings;
    } else {
      EXPECT_DOUBLE_EQ(next, a[k].h) << k;
    }
  }
  EXPECT_EQ(out.substeps, kept);
  EXPECT_EQ(out.rejected, static_cast<int>(a.size()) - kept);
  return out;
}

TEST(BackwardEulerStepControl, HalvesAtTheUpperLimitDoublesAtTheLowerAndStaysInBounds) {
  const double hMin = 1.0 / 8192, hMax = 1.0 / 64;  // s
  // The system: the iteration count rises with the step (M - h^2 K grows worse conditioned).
  std::vector<int> counts;
  for (double h = hMin; h <= hMax; h *= 2) counts.push_back(iterationsOfOneStep(h));
  ASSERT_EQ(counts.size(), 8u);
  for (size_t k = 1; k < counts.size(); ++k) EXPECT_GT(counts[k], counts[k - 1]) << k;
  ASSERT_GE(counts.back(), 3 * counts.front());

  BackwardEulerParams p = countingParams();
  p.adaptive = true;
  p.lowerIterations = counts[2];  // the count at 4 h_min
  p.upperIterations = counts[5];  // the count at 32 h_min
  p.minStep = hMin;
  p.maxStep = hMax;
  p.initialStep = hMax;  // far above the upper limit: halved and redone
  const ControlRun fromAbove = runAdaptive(p);
  EXPECT_GE(fromAbove.halvings, 2);
  EXPECT_GE(fromAbove.rejected, 2);
  p.initialStep = hMin;  // far below the lower limit: doubled
  const ControlRun fromBelow = runAdaptive(p);
  EXPECT_GE(fromBelow.doublings, 2);
  // Both settle between the limits: about 8 to 16 h_min, far from where they started.
  for (const ControlRun* run : {&fromAbove, &fromBelow}) {
    EXPECT_GT(run->attempts.back().planned, 2 * hMin);
    EXPECT_LT(run->attempts.back().planned, hMax / 2);
  }
}

// At h_min a step is kept whatever its count: the frame goes on instead of failing.
TEST(BackwardEulerStepControl, AStepAtTheShortestLengthIsKept) {
  BackwardEulerParams p = countingParams();
  p.adaptive = true;
  p.lowerIterations = 0;
  p.upperIterations = 1;  // every step needs more
  p.minStep = 1e-3;
  p.initialStep = 4e-3;
  BackwardEulerIntegrator be(p);
  auto s = beam();
  const StepReport r = be.advance(*s, 0.01);
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_EQ(r.rejected, 2);  // 4 ms and 2 ms
  EXPECT_EQ(r.substeps, 10);
  EXPECT_NEAR(r.lastStep, 1e-3, 1e-15);
  EXPECT_EQ(s->state.t, 0.01);
}

}  // namespace
}  // namespace tt
