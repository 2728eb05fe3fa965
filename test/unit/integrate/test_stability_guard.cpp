// The stability guard (stability_guard.h): explosions caught and recovered by halving,
// inverted tets caught for models that cannot take them, unrecoverable cases reported with
// the state restored, and no change at all to a run that needs no help. Also which models
// tolerate inversion, and the scene key.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>

#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/explicit_euler.h"
#include "tissue_trainer/core/integrate/newtonian.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/mesh/mesh_order.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/gravity.h"
#include "tissue_trainer/core/model/stvk_displacement.h"
#include "tissue_trainer/core/model/tensor_mass.h"
#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/scene/scene_runner.h"

namespace tt {
namespace {

constexpr double kFrame = 0.01;  // s

// A 2 cm block of 3 x 3 x 3 nodes (40 tets), bottom fixed, under gravity, with mass damping.
// Stiff enough (E = 200 kPa) that explicit steps must be well below a millisecond.
std::unique_ptr<System> stiffBlock(double rayleigh = 0.0) {
  Mesh mesh = boxGrid(3, 3, 3, Eigen::Vector3d(0.02, 0.02, 0.02), TetSplit::kFiveMirrored);
  for (int n = 0; n < mesh.numNodes(); ++n)
    if (mesh.rest(2, n) == 0.0) mesh.nodeTags[n] = kFixedAll;
  auto s = std::make_unique<System>(mesh, std::vector<Material>{Material::isotropic(2e5, 0.3, 1000)});
  s->models.push_back(std::make_unique<EdgeLengthModel>(s->mesh, s->materials));
  s->models.push_back(std::make_unique<GravityModel>(s->mass, Eigen::Vector3d(0, 0, -9.81)));
  s->damping = rayleigh * s->mass;
  s->updateConstraints();
  s->prescribe(0.0, s->state.x, s->state.v);
  return s;
}

// Highest angular frequency of the free DOFs at rest: sqrt of the largest eigenvalue of
// -M^-1/2 K M^-1/2.
double highestFrequency(const System& s) {
  SparseMatrix K;
  s.assembleStiffness(s.state.x, K);
  const Eigen::MatrixXd dense(K);
  std::vector<int> free;
  for (int dof = 0; dof < s.numDofs(); ++dof)
    if (!s.isConstrained[dof]) free.push_back(dof);
  const int n = static_cast<int>(free.size());
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      A(i, j) = -dense(free[i], free[j]) / std::sqrt(s.mass[free[i]] * s.mass[free[j]]);
  return std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues().maxCoeff());
}

// The largest stable step at rest for the top mode (omega) with mass damping alpha.
// Forward Euler, unstable at every step without damping, gets alpha = 2 omega (stable for
// h < 1 / omega). Symplectic Euler gets alpha = omega / 50 (the comparison with a small-step
// run needs the top modes, whose phase no step near the limit gets right, to die out); it is
// stable while omega^2 h^2 + 2 alpha h < 4.
struct ExplicitCase {
  bool symplectic;
  double rayleigh, criticalStep;
};

ExplicitCase explicitCase(bool symplectic) {
  const double omega = highestFrequency(*stiffBlock());
  if (!symplectic) return {false, 2.0 * omega, 1.0 / omega};
  const double alpha = 0.02 * omega;
  return {true, alpha, (std::sqrt(alpha * alpha + 4.0 * omega * omega) - alpha) / (omega * omega)};
}

bool finiteAndCalm(const System& s) {
  return s.state.x.allFinite() && s.state.v.allFinite() &&
         s.kineticEnergy(s.state.v) + s.potentialEnergy(s.state.x) < 1.0;  // J; the block holds ~1e-6
}

// Advances `frames` frames; false at the first failed one.
bool run(Integrator& integrator, System& s, int frames, StepReport* last = nullptr) {
  for (int f = 0; f < frames; ++f) {
    const StepReport r = integrator.advance(s, kFrame);
    if (last) *last = r;
    if (!r.ok) return false;
  }
  return true;
}

TEST(StabilityGuard, ExplicitStepsAboveTheLimitExplodeWithoutTheGuard) {
  for (bool symplectic : {false, true}) {
    const ExplicitCase c = explicitCase(symplectic);
    EXPECT_GT(kFrame, 8.0 * c.criticalStep);  // well above the limit
    auto s = stiffBlock(symplectic ? 0.0 : c.rayleigh);
    ExplicitEulerIntegrator plain(ExplicitEulerParams{kFrame, symplectic});
    for (int f = 0; f < 10 && finiteAndCalm(*s); ++f) plain.advance(*s, kFrame);
    EXPECT_FALSE(finiteAndCalm(*s)) << plain.name();
  }
}

TEST(StabilityGuard, HalvesExplicitStepsUntilStableAndFollowsASmallStepRun) {
  for (bool symplectic : {false, true}) {
    const ExplicitCase c = explicitCase(symplectic);
    EXPECT_LT(kFrame / 64, c.criticalStep);  // within reach of 6 halvings
    auto s = stiffBlock(c.rayleigh), reference = stiffBlock(c.rayleigh);
    StabilityGuard guard(std::make_unique<ExplicitEulerIntegrator>(ExplicitEulerParams{kFrame, symplectic}));
    ExplicitEulerIntegrator fine(ExplicitEulerParams{1e-6, symplectic});
    const Eigen::Map<const Eigen::VectorXd> rest(s->mesh.rest.data(), s->numDofs());
    double error = 0.0, sag = 0.0;  // largest over the frames (m)
    for (int f = 0; f < 10; ++f) {
      const StepReport r = guard.advance(*s, kFrame);
      ASSERT_TRUE(r.ok) << r.failure;
      EXPECT_LE(r.lastStep, c.criticalStep) << "frame " << f;
      ASSERT_TRUE(fine.advance(*reference, kFrame).ok);
      error = std::max(error, (s->state.x - reference->state.x).cwiseAbs().maxCoeff());
      sag = std::max(sag, (reference->state.x - rest).cwiseAbs().maxCoeff());
    }
    EXPECT_TRUE(finiteAndCalm(*s));
    EXPECT_EQ(guard.stats().frames, 10);
    EXPECT_GT(guard.stats().recoveries, 0);
    EXPECT_GE(guard.stats().halvings, guard.stats().recoveries);
    EXPECT_EQ(guard.stats().failures, 0);
    EXPECT_FALSE(guard.stats().lastReason.empty());
    EXPECT_NEAR(s->state.t, 10 * kFrame, 1e-12);
    EXPECT_GT(sag, 1e-6);
    // On the way, steps near the limit get the top modes' phase wrong (16% of the sag seen
    // for symplectic Euler, 0.4% for the overdamped forward Euler); once they are damped out
    // the states agree (0.5% and 1e-6 of the sag seen).
    EXPECT_LT(error, 0.25 * sag) << guard.name() << " against steps of 1 us";
    EXPECT_LT((s->state.x - reference->state.x).cwiseAbs().maxCoeff(), 0.02 * sag) << guard.name();
  }
}

// One symplectic step per frame, 10 % above the limit: the top mode gains about 4.4x a step,
// less than the 10x a frame allows, so only the excess carried over frames shows it (its
// message names the frames it was carried over).
TEST(StabilityGuard, SlowGrowthOverManyFramesIsCaughtByTheCarriedExcess) {
  const ExplicitCase c = explicitCase(true);
  const double h = 1.1 * c.criticalStep;
  const int frames = 300;
  // The largest |kinetic + elastic + gravity energy| over the frames; infinite once a frame fails.
  const auto largestEnergy = [&](Integrator& integrator, System& s) {
    double largest = 0.0;
    for (int f = 0; f < frames; ++f) {
      if (!integrator.advance(s, h).ok) return std::numeric_limits<double>::infinity();
      largest = std::max(largest, std::abs(s.kineticEnergy(s.state.v) + s.potentialEnergy(s.state.x)));
    }
    return largest;
  };
  auto bare = stiffBlock(c.rayleigh), guarded = stiffBlock(c.rayleigh), fine = stiffBlock(c.rayleigh);
  ExplicitEulerIntegrator plain(ExplicitEulerParams{h, true});
  StabilityGuard guard(std::make_unique<ExplicitEulerIntegrator>(ExplicitEulerParams{h, true}));
  ExplicitEulerIntegrator quarter(ExplicitEulerParams{h / 4, true});
  const double bareLargest = largestEnergy(plain, *bare);
  const double guardedLargest = largestEnergy(guard, *guarded);
  const double fineLargest = largestEnergy(quarter, *fine);
  std::printf("  largest |energy| over %d frames of %.3g s: bare %.3g J, guarded %.3g J, steps of "
              "h/4 %.3g J; guard halvings %ld\n",
              frames, h, bareLargest, guardedLargest, fineLargest, guard.stats().halvings);
  EXPECT_GT(bareLargest, 1e3 * fineLargest);  // the bare run blows up (or fails)
  EXPECT_LT(guardedLargest, 1.1 * fineLargest);
  EXPECT_GT(guard.stats().halvings, 0);
  EXPECT_EQ(guard.stats().failures, 0);
  EXPECT_NE(guard.stats().lastReason.find("over the last"), std::string::npos)
      << guard.stats().lastReason;
}

TEST(StabilityGuard, LaterFramesKeepTheShorterStepAndTryALongerOneAfterRelaxAfterFrames) {
  const ExplicitCase c = explicitCase(true);
  auto s = stiffBlock(c.rayleigh);
  StabilityGuardParams p;
  p.relaxAfter = 3;
  StabilityGuard guard(std::make_unique<ExplicitEulerIntegrator>(ExplicitEulerParams{kFrame, true}), p);
  const StepReport first = guard.advance(*s, kFrame);
  const GuardFrame firstGuard = guard.lastFrame();
  ASSERT_TRUE(first.ok) << first.failure;
  ASSERT_GT(firstGuard.halvings, 0);
  for (int f = 1; f <= 3; ++f) {  // no rollback, the step that passed
    const StepReport r = guard.advance(*s, kFrame);
    const GuardFrame rGuard = guard.lastFrame();
    EXPECT_EQ(rGuard.halvings, 0) << "frame " << f << ": " << rGuard.reason;
    EXPECT_EQ(r.lastStep, first.lastStep) << "frame " << f;
  }
  const StepReport relaxed = guard.advance(*s, kFrame);  // tries twice the step: unstable
  const GuardFrame relaxedGuard = guard.lastFrame();
  EXPECT_EQ(relaxedGuard.halvings, 1) << relaxedGuard.reason;
  EXPECT_EQ(relaxed.lastStep, first.lastStep);
  EXPECT_EQ(guard.stats().recoveries, 2);
}

// Two tets sharing face (0, 1, 2): tet 0 above it (node 3), tet 1 below (node 4). Nodes 0-3
// fixed, node 4 driven up through the face within one frame, which inverts tet 1. renumbered:
// the mesh as the scene loader may reorder a file's (mesh_order.h): tets swapped, nodes
// reversed, the file's numbers kept in mesh.numbering.
std::unique_ptr<System> pushThrough(bool linearModel, bool renumbered = false) {
  Mesh mesh;
  mesh.rest.resize(3, 5);
  mesh.rest << 0, 1, 0, 0, 0,  //
      0, 0, 1, 0, 0,           //
      0, 0, 0, 1, -1;
  mesh.rest *= 0.01;
  mesh.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  mesh.fillDefaults();
  for (int n = 0; n < 4; ++n) mesh.nodeTags[n] = kFixedAll;
  if (renumbered) applyOrder(mesh, {{4, 3, 2, 1, 0}, {1, 0}});
  auto s = std::make_unique<System>(mesh, std::vector<Material>{Material::isotropic(3e3, 0.4, 1000)});
  if (linearModel) s->models.push_back(std::make_unique<TensorMassModel>(s->mesh, s->materials));
  else s->models.push_back(std::make_unique<EdgeLengthModel>(s->mesh, s->materials));
  ControlledSet set;
  set.nodes = {s->mesh.numbering.nodeFromFile(4)};
  set.path.times = {0.0, kFrame};
  set.path.offsets = {Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 0.015)};
  s->controlled.push_back(set);
  s->updateConstraints();
  return s;
}

TEST(StabilityGuard, InvertedTetOfAModelThatCannotTakeItFailsTheFrameNamingTheTet) {
  auto s = pushThrough(false);
  const State before = s->state;
  StabilityGuard guard(std::make_unique<BackwardEulerIntegrator>());
  const StepReport r = guard.advance(*s, kFrame);
  const GuardFrame rGuard = guard.lastFrame();
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("tet 1 inverted or flat"), std::string::npos) << r.failure;
  EXPECT_NE(r.failure.find("after 6 halvings"), std::string::npos) << r.failure;
  EXPECT_NE(r.failure.find("in t = ["), std::string::npos) << r.failure;
  EXPECT_EQ(s->state.x, before.x);
  EXPECT_EQ(s->state.t, before.t);
  EXPECT_EQ(guard.stats().failures, 1);
  EXPECT_EQ(guard.stats().halvings, rGuard.halvings);
  EXPECT_GE(rGuard.halvings, 6);
}

TEST(StabilityGuard, MessageNamesTheTetByItsFileNumberInAReorderedMesh) {
  auto s = pushThrough(false, true);
  ASSERT_EQ(s->mesh.numbering.tetFromFile(1), 0);
  StabilityGuard guard(std::make_unique<BackwardEulerIntegrator>());
  const StepReport r = guard.advance(*s, kFrame);
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("tet 1 inverted or flat"), std::string::npos) << r.failure;
}

TEST(StabilityGuard, MessageNamesTheDofByItsFileNodeInAReorderedMesh) {
  auto s = pushThrough(false, true);
  s->externalForce[3 * s->mesh.numbering.nodeFromFile(4) + 1] =
      std::numeric_limits<double>::quiet_NaN();
  StabilityGuard guard(std::make_unique<BackwardEulerIntegrator>());
  const StepReport r = guard.advance(*s, kFrame);
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("non-finite external force at DOF 13 (node 4 y)"), std::string::npos)
      << r.failure;
}

TEST(StabilityGuard, LinearModelToleratesTheSameInversion) {
  auto s = pushThrough(true);
  StabilityGuard guard(std::make_unique<BackwardEulerIntegrator>());
  const StepReport r = guard.advance(*s, kFrame);
  const GuardFrame rGuard = guard.lastFrame();
  EXPECT_TRUE(r.ok) << r.failure;
  EXPECT_EQ(rGuard.halvings, 0);
  EXPECT_LT(tetVolume(Eigen::Map<const Eigen::Matrix3Xd>(s->state.x.data(), 3, 5), s->mesh.tets[1]), 0.0);
}

TEST(StabilityGuard, NonFiniteExternalForceIsUnrecoverableAndRestoresTheState) {
  auto s = stiffBlock();
  StabilityGuard guard(std::make_unique<BackwardEulerIntegrator>());
  ASSERT_TRUE(run(guard, *s, 2));
  const State good = s->state;
  s->externalForce[3 * 20 + 1] = std::numeric_limits<double>::quiet_NaN();
  const StepReport r = guard.advance(*s, kFrame);
  const GuardFrame rGuard = guard.lastFrame();
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("stability guard: non-finite external force at DOF 61 (node 20 y)"),
            std::string::npos) << r.failure;
  EXPECT_EQ(rGuard.halvings, 0);  // halving cannot help: no retries
  EXPECT_EQ(s->state.x, good.x);
  EXPECT_EQ(s->state.v, good.v);
  EXPECT_EQ(s->state.t, good.t);
  EXPECT_EQ(guard.stats().failures, 1);
}

// An integrator that reports success while its state is not finite: the guard does not trust
// the report. It steps backward Euler, then spoils one velocity while the step is longer than
// 2 ms, so that halving the frame (5 ms, 2.5 ms, 1.25 ms pieces) recovers it.
class SpoilsLongSteps : public Integrator {
 public:
  const char* name() const override { return "spoils_long_steps"; }
  bool needsStiffness() const override { return true; }
  StepReport advance(System& system, double frameTime) override {
    StepReport r = inner_.advance(system, frameTime);
    if (frameTime > 2e-3) system.state.v[3 * 20 + 2] = std::numeric_limits<double>::infinity();
    return r;
  }

 private:
  BackwardEulerIntegrator inner_;
};

TEST(StabilityGuard, NonFiniteStateIsCaughtEvenWhenTheIntegratorReportsSuccess) {
  auto s = stiffBlock();
  StabilityGuard guard(std::make_unique<SpoilsLongSteps>());
  const StepReport r = guard.advance(*s, kFrame);
  const GuardFrame rGuard = guard.lastFrame();
  EXPECT_TRUE(r.ok) << r.failure;
  EXPECT_EQ(rGuard.halvings, 3);  // 10 ms, 5 ms and 2.5 ms pieces spoilt; 1.25 ms ones not
  EXPECT_NE(rGuard.reason.find("non-finite velocity at DOF 62 (node 20 z)"), std::string::npos)
      << rGuard.reason;
  EXPECT_TRUE(s->state.x.allFinite() && s->state.v.allFinite());
  EXPECT_NEAR(s->state.t, kFrame, 1e-15);
}

// Takes 4 ms per call on a simulated wall clock (the guard's wallClock), and spoils the
// velocity of the step that ends the frame: every attempt runs all its pieces and fails at the
// last. The simulated clock makes the budget's effect exact, whatever else the machine runs.
constexpr double kPieceWallTime = 0.004;

class SlowAndSpoilsTheFrameEnd : public Integrator {
 public:
  explicit SlowAndSpoilsTheFrameEnd(double& clock) : clock_(clock) {}
  const char* name() const override { return "slow_and_spoils_the_frame_end"; }
  StepReport advance(System& system, double frameTime) override {
    clock_ += kPieceWallTime;
    pieces.push_back(frameTime);
    system.state.t += frameTime;
    if (spoil && system.state.t > kFrame * (1.0 - 1e-9)) system.state.v[0] = std::nan("");
    return {};
  }
  std::vector<double> pieces;  // the length of every call
  bool spoil = true;

 private:
  double& clock_;
};

StabilityGuardParams withClock(double& clock, double budget) {
  StabilityGuardParams p;
  p.wallBudget = budget;
  p.wallClock = [&clock] { return clock; };
  return p;
}

TEST(StabilityGuard, AWallTimeBudgetEndsTheRetriesOfAFrameThatCannotBeMadeStable) {
  auto s = stiffBlock();
  const State start = s->state;
  double clock = 0.0;
  StabilityGuard unlimited(std::make_unique<SlowAndSpoilsTheFrameEnd>(clock),
                           withClock(clock, 0.0));
  const StepReport all = unlimited.advance(*s, kFrame);
  const GuardFrame allGuard = unlimited.lastFrame();
  EXPECT_FALSE(all.ok);
  EXPECT_EQ(allGuard.halvings, 6);  // 1 + 2 + ... + 64 = 127 pieces of 4 ms
  EXPECT_NEAR(all.wallSeconds, 127 * kPieceWallTime, 1e-9);

  const StabilityGuardParams p = withClock(clock, 3 * kFrame);  // three frame periods
  auto slow = std::make_unique<SlowAndSpoilsTheFrameEnd>(clock);
  SlowAndSpoilsTheFrameEnd& calls = *slow;
  StabilityGuard budgeted(std::move(slow), p);
  const StepReport r = budgeted.advance(*s, kFrame);
  const GuardFrame rGuard = budgeted.lastFrame();
  ASSERT_FALSE(r.ok);
  EXPECT_LT(rGuard.halvings, 6);
  EXPECT_LE(r.wallSeconds, p.wallBudget + kPieceWallTime + 1e-9);  // the budget, one more piece
  EXPECT_NE(r.failure.find("the frame's wall-time budget of 30 ms is spent"), std::string::npos)
      << r.failure;
  EXPECT_NE(rGuard.reason.find("non-finite velocity at DOF 0"), std::string::npos) << rGuard.reason;
  EXPECT_EQ(s->state.x, start.x);  // the last good state is kept
  EXPECT_EQ(s->state.v, start.v);
  EXPECT_EQ(s->state.t, start.t);

  // The next frame starts one halving deeper than the last attempt of this one.
  calls.pieces.clear();
  budgeted.advance(*s, kFrame);
  ASSERT_FALSE(calls.pieces.empty());
  EXPECT_NEAR(calls.pieces.front(), kFrame / (1 << (rGuard.halvings + 1)), 1e-15);
}

// Takes 4 ms per call on the simulated wall clock and spoils only a whole-frame step: the frame
// passes once it is halved.
class SlowAndSpoilsWholeFrames : public Integrator {
 public:
  explicit SlowAndSpoilsWholeFrames(double& clock) : clock_(clock) {}
  const char* name() const override { return "slow_and_spoils_whole_frames"; }
  StepReport advance(System& system, double frameTime) override {
    clock_ += kPieceWallTime;
    system.state.t += frameTime;
    if (frameTime > 0.75 * kFrame) system.state.v[0] = std::nan("");
    return {};
  }

 private:
  double& clock_;
};

// Where one step takes longer than the fixed budget (a large mesh), a budget counted in typical
// steps still lets the frame that fails be halved.
TEST(StabilityGuard, ABudgetInTypicalStepsLetsASlowFrameBeHalved) {
  constexpr double kFixedBudget = 0.001;  // shorter than one 4 ms step
  auto fixedOnly = stiffBlock(), scaled = stiffBlock();
  double clock = 0.0;
  StabilityGuard fixed(std::make_unique<SlowAndSpoilsWholeFrames>(clock), withClock(clock, kFixedBudget));
  const StepReport failed = fixed.advance(*fixedOnly, kFrame);
  const GuardFrame failedGuard = fixed.lastFrame();
  EXPECT_FALSE(failed.ok);
  EXPECT_EQ(failedGuard.halvings, 0);
  EXPECT_NE(failed.failure.find("wall-time budget of 1 ms is spent"), std::string::npos) << failed.failure;

  StabilityGuardParams p = withClock(clock, kFixedBudget);
  p.wallBudgetSteps = 3.0;
  StabilityGuard steps(std::make_unique<SlowAndSpoilsWholeFrames>(clock), p);
  const StepReport halved = steps.advance(*scaled, kFrame);
  const GuardFrame halvedGuard = steps.lastFrame();
  EXPECT_TRUE(halved.ok) << halved.failure;
  EXPECT_EQ(halvedGuard.halvings, 1);
  EXPECT_NEAR(scaled->state.t, kFrame, 1e-15);
  EXPECT_NEAR(steps.wallBudget(), 3 * kPieceWallTime, 1e-12);  // every piece took 4 ms
  EXPECT_NEAR(halved.wallSeconds, 3 * kPieceWallTime, 1e-9);   // 1 + 2 pieces
}

// A frame that starts deep (after one the budget ended) and passes, but whose pieces take
// longer than the budget: it ends early with the pieces it made instead of stalling the node.
TEST(StabilityGuard, AFrameThatStartsDeepEndsEarlyWithinTheBudgetAndKeepsItsPieces) {
  auto s = stiffBlock();
  double clock = 0.0;
  const StabilityGuardParams p = withClock(clock, 3 * kFrame);
  auto slow = std::make_unique<SlowAndSpoilsTheFrameEnd>(clock);
  SlowAndSpoilsTheFrameEnd& calls = *slow;
  StabilityGuard guard(std::move(slow), p);
  ASSERT_FALSE(guard.advance(*s, kFrame).ok);  // the budget ends it: the next starts deeper
  calls.spoil = false;
  double t = s->state.t;
  for (int frame = 0; frame < 3; ++frame) {
    calls.pieces.clear();
    const StepReport r = guard.advance(*s, kFrame);
    const GuardFrame rGuard = guard.lastFrame();
    ASSERT_TRUE(r.ok) << r.failure;
    const int deep = static_cast<int>(std::lround(kFrame / calls.pieces.front()));
    ASSERT_GE(deep, 16);  // 16 pieces of 4 ms and more: beyond the 30 ms budget
    EXPECT_TRUE(rGuard.cutShort);
    EXPECT_LT(calls.pieces.size(), static_cast<size_t>(deep));
    EXPECT_LE(r.wallSeconds, p.wallBudget + kPieceWallTime + 1e-9);  // the budget, one more piece
    EXPECT_NEAR(s->state.t - t, calls.pieces.size() * calls.pieces.front(), 1e-15);
    EXPECT_NE(rGuard.reason.find("frame cut short for the wall-time budget"), std::string::npos)
        << rGuard.reason;
    EXPECT_EQ(rGuard.halvings, 0);
    t = s->state.t;
  }
  EXPECT_GT(s->state.t, 0.0);
  EXPECT_LT(s->state.t, 3 * kFrame);
}

TEST(StabilityGuard, NoHalvingsAllowedFailsAtOnceWithTheCheckAndRestores) {
  // Within its first frame the symplectic step (h = 10 ms) multiplies the energy, finite.
  auto s = stiffBlock();
  StabilityGuardParams p;
  p.maxHalvings = 0;
  StabilityGuard guard(std::make_unique<ExplicitEulerIntegrator>(ExplicitEulerParams{kFrame, true}), p);
  const State start = s->state;
  const StepReport r = guard.advance(*s, kFrame);
  const GuardFrame rGuard = guard.lastFrame();
  ASSERT_FALSE(r.ok);
  EXPECT_EQ(r.failure.rfind("stability guard: energy grew by ", 0), 0u) << r.failure;
  EXPECT_NE(r.failure.find("in t = [0, 0.01] s, still failing after 0 halvings"),
            std::string::npos) << r.failure;
  EXPECT_NE(r.failure.find("state restored"), std::string::npos) << r.failure;
  EXPECT_EQ(r.failure.find('\n'), std::string::npos);
  EXPECT_EQ(s->state.x, start.x);
  EXPECT_EQ(s->state.v, start.v);
  EXPECT_EQ(s->state.t, start.t);
  EXPECT_EQ(rGuard.halvings, 0);
  EXPECT_EQ(guard.stats().failures, 1);
  EXPECT_EQ(guard.stats().recoveries, 0);
}

// Guarded and plain runs of the same integrator from the same state: every bit equal.
void expectIdentical(std::unique_ptr<Integrator> a, std::unique_ptr<Integrator> b, int frames) {
  auto s1 = stiffBlock(2.0), s2 = stiffBlock(2.0);
  for (System* s : {s1.get(), s2.get()}) {  // a controlled corner too, for the work term
    ControlledSet set;
    set.nodes = {26};
    set.path.times = {0.0, 0.05};
    set.path.offsets = {Eigen::Vector3d::Zero(), Eigen::Vector3d(0.002, 0, 0.001)};
    s->controlled.push_back(set);
    s->updateConstraints();
  }
  StabilityGuard guard(std::move(b));
  for (int f = 0; f < frames; ++f) {
    const StepReport plain = a->advance(*s1, kFrame);
    const StepReport guarded = guard.advance(*s2, kFrame);
    const GuardFrame guardedGuard = guard.lastFrame();
    ASSERT_TRUE(plain.ok && guarded.ok) << guarded.failure << guardedGuard.reason;
    EXPECT_EQ(guarded.substeps, plain.substeps);
  }
  EXPECT_EQ(s1->state.x, s2->state.x) << guard.name();
  EXPECT_EQ(s1->state.v, s2->state.v) << guard.name();
  EXPECT_EQ(s1->state.t, s2->state.t) << guard.name();
  EXPECT_EQ(guard.stats().frames, frames);
  EXPECT_EQ(guard.stats().recoveries, 0) << guard.stats().lastReason;
  EXPECT_EQ(guard.stats().halvings, 0);
  EXPECT_TRUE(guard.stats().lastReason.empty()) << guard.stats().lastReason;
}

TEST(StabilityGuard, WellBehavedRunsAreBitIdenticalToTheUnwrappedIntegrator) {
  expectIdentical(std::make_unique<BackwardEulerIntegrator>(),
                  std::make_unique<BackwardEulerIntegrator>(), 20);
  expectIdentical(std::make_unique<NewtonianIntegrator>(NewtonianParams{1e-5}),
                  std::make_unique<NewtonianIntegrator>(NewtonianParams{1e-5}), 10);
  expectIdentical(std::make_unique<ExplicitEulerIntegrator>(ExplicitEulerParams{1e-5, true}),
                  std::make_unique<ExplicitEulerIntegrator>(ExplicitEulerParams{1e-5, true}), 10);
}

// One tet with node 3 mirrored through the plane of face (0, 1, 2): F is a reflection.
TEST(StabilityGuard, InversionToleranceMatchesWhatTheModelsDoWithAMirroredTet) {
  Mesh mesh;
  mesh.rest.resize(3, 4);
  mesh.rest << 0, 0.01, 0, 0.002, 0, 0, 0.012, 0.003, 0, 0, 0, 0.01;
  mesh.tets = {{0, 1, 2, 3}};
  mesh.fillDefaults();
  const std::vector<Material> materials{Material::isotropic(3e3, 0.4, 1000)};
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(mesh.rest.data(), 12);
  Eigen::VectorXd stretched = x;
  stretched[11] *= 1.1;
  Eigen::VectorXd mirrored = x;
  mirrored[11] = -mirrored[11];  // face (0, 1, 2) lies in z = 0
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(12);

  const std::vector<std::unique_ptr<ForceModel>> models = [&] {
    std::vector<std::unique_ptr<ForceModel>> m;
    m.push_back(std::make_unique<EdgeLengthModel>(mesh, materials));
    m.push_back(std::make_unique<EdgeLengthModel>(mesh, materials, EdgeLengthPath::kLiteral));
    m.push_back(std::make_unique<StvkDisplacementModel>(mesh, materials));
    m.push_back(std::make_unique<TensorMassModel>(mesh, materials));
    return m;
  }();
  for (const auto& model : models) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(12);
    const double scale = model->energy(stretched);
    const double energy = model->addForce(mirrored, v, f);
    // A model tolerates inversion when the mirrored tet is far from a rest state: high energy
    // and a force on node 3 back up through the face.
    const bool restores = energy > 10 * scale && f[11] > 0.0;
    EXPECT_EQ(model->toleratesInversion(), restores)
        << model->name() << ": energy " << energy << " (10% stretch: " << scale << "), f_z " << f[11];
  }
  EXPECT_TRUE(GravityModel(Eigen::VectorXd::Ones(12), Eigen::Vector3d::Zero()).toleratesInversion());
}

std::string writeScene(const std::string& name, const std::string& extra) {
  const auto dir = std::filesystem::temp_directory_path() / "tt_guard_tests";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << "name: block\n"
                         "mesh: {generator: box, nodes: [3, 3, 3], size: [0.02, 0.02, 0.02]}\n"
                         "materials: [{young_modulus: 200000, poisson_ratio: 0.3, density: 1000}]\n"
                         "force_models: [{type: edge_length}]\n"
                         "integrator: {type: symplectic_euler, time_step: 0.01}\n"
                         "boundary: {fixed: [{plane: {point: [0, 0, 0], normal: [0, 0, 1]}}]}\n"
                         "loads: {gravity: [0, 0, -9.81]}\n"
                         "run: {frame_time: 0.01, duration: 0.1}\n"
                      << extra;
  return path.string();
}

TEST(StabilityGuard, SceneKeyDefaultsToOnAndCanBeTunedOrTurnedOff) {
  Scene byDefault = loadScene(writeScene("default.yaml", ""));
  auto* guard = dynamic_cast<StabilityGuard*>(byDefault.integrator.get());
  ASSERT_NE(guard, nullptr);
  EXPECT_EQ(guard->params().maxHalvings, 6);
  EXPECT_STREQ(guard->name(), "symplectic_euler");
  EXPECT_NE(dynamic_cast<ExplicitEulerIntegrator*>(&unguarded(*byDefault.integrator)), nullptr);

  Scene tuned = loadScene(writeScene("tuned.yaml",
      "stability_guard: {max_halvings: 3, energy_growth: 4, energy_slack: 0, min_volume_ratio: 0.1}\n"));
  guard = dynamic_cast<StabilityGuard*>(tuned.integrator.get());
  ASSERT_NE(guard, nullptr);
  EXPECT_EQ(guard->params().maxHalvings, 3);
  EXPECT_EQ(guard->params().energyGrowth, 4.0);
  EXPECT_EQ(guard->params().energySlack, 0.0);
  EXPECT_EQ(guard->params().minVolumeRatio, 0.1);

  Scene off = loadScene(writeScene("off.yaml", "stability_guard: {enabled: false}\n"));
  EXPECT_EQ(dynamic_cast<StabilityGuard*>(off.integrator.get()), nullptr);
  EXPECT_NE(dynamic_cast<ExplicitEulerIntegrator*>(off.integrator.get()), nullptr);
}

TEST(StabilityGuard, SceneRunnerSumsTheGuardCountsAndLogsHalvings) {
  Scene guarded = loadScene(writeScene("run.yaml", "output: {csv: true}\n"));
  RunOptions options;
  options.outDir = (std::filesystem::temp_directory_path() / "tt_guard_tests" / "out").string();
  const RunSummary summary = runScene(guarded, options);
  EXPECT_TRUE(summary.ok) << summary.failure;
  EXPECT_EQ(summary.guard.frames, 10);
  EXPECT_GT(summary.guard.recoveries, 0);
  EXPECT_GE(summary.guard.halvings, summary.guard.recoveries);
  EXPECT_EQ(summary.guard.failures, 0);
  std::ifstream csv(options.outDir + "/block.csv");
  std::string header, line;
  std::getline(csv, header);
  std::getline(csv, line);
  const size_t halvings = header.find(",ok,halvings,");
  ASSERT_NE(halvings, std::string::npos) << header;
  // The field of `halvings` in the first frame: it needed some.
  const long column = std::count(header.begin(), header.begin() + halvings, ',') + 2;
  size_t at = 0;
  for (long k = 0; k < column; ++k) at = line.find(',', at) + 1;
  EXPECT_NE(line.substr(at, line.find(',', at) - at), "0") << line;

  Scene plain = loadScene(writeScene("run_off.yaml", "stability_guard: {enabled: false}\n"));
  const RunSummary unguarded = runScene(plain, {});
  EXPECT_EQ(unguarded.guard.frames, 0);
  EXPECT_FALSE(unguarded.ok && std::abs(unguarded.last.kineticEnergy) < 1.0)
      << "without the guard the same scene should fail or explode";
}

}  // namespace
}  // namespace tt
