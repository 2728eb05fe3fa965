// The Adams-Bashforth-Moulton predictor-corrector (integrate/abm3.h): measured orders at fixed
// step with both starting methods, the halving/doubling control on a stiff transient and on a
// smooth motion, fixed nodes, non-finite states, every force model, and its scene keys.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <vector>

#include "../scene/scene_test_util.h"
#include "oscillators.h"
#include "tissue_trainer/core/integrate/abm3.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace {

using namespace oscillators;

Abm3Params fixedStep(double h, Abm3Params::Start start) {
  Abm3Params p;
  p.adaptive = false;
  p.timeStep = h;
  p.start = start;
  return p;
}

// u = e^{-beta t} (A cos wd t + B sin wd t) for m u'' + c u' + k u = 0, underdamped.
double dampedExact(double m, double c, double k, double u0, double v0, double t) {
  const double beta = c / (2.0 * m), wd = std::sqrt(k / m - beta * beta);
  return std::exp(-beta * t) * (u0 * std::cos(wd * t) + (v0 + beta * u0) / wd * std::sin(wd * t));
}

// y' = -y as the velocity of a damped mass without a spring (c = m = 1): v = v0 e^{-t} and
// x = x0 + v0 (1 - e^{-t}). Error at t = 1 in x and v, N = 1/h steps in one frame.
double decayError(int n, Abm3Params::Start start) {
  Oscillators o = harmonic(1.0);
  o.k = Eigen::VectorXd::Zero(12);
  System s = o.build();
  Abm3Integrator integrator(fixedStep(1.0 / n, start));
  const StepReport r = integrator.advance(s, 1.0);
  EXPECT_TRUE(r.ok) << r.failure;
  EXPECT_EQ(r.substeps, n);
  const double e = std::exp(-1.0);
  const Eigen::VectorXd u = s.state.x - restVector(s);
  return std::max((u - o.u0 - o.v0 * (1.0 - e)).lpNorm<Eigen::Infinity>(),
                  (s.state.v - o.v0 * e).lpNorm<Eigen::Infinity>());
}

// The undamped oscillators of period 1 s at t = 1 (positions).
double harmonicError(int n, Abm3Params::Start start) {
  const Oscillators o = harmonic(0.0);
  System s = o.build();
  Abm3Integrator integrator(fixedStep(1.0 / n, start));
  const StepReport r = integrator.advance(s, 1.0);
  EXPECT_TRUE(r.ok) << r.failure;
  EXPECT_EQ(r.substeps, n);
  return o.maxError(s);
}

double measuredOrder(double (*error)(int, Abm3Params::Start), Abm3Params::Start start,
                     const char* label) {
  std::vector<double> hs, errs;
  for (int n : {50, 100, 200, 400}) {
    hs.push_back(1.0 / n);
    errs.push_back(error(n, start));
  }
  const double slope = logSlope(hs, errs);
  std::printf("[ order    ] abm3 %-30s errors %.3e %.3e %.3e %.3e, slope %.3f\n", label,
              errs[0], errs[1], errs[2], errs[3], slope);
  return slope;
}

TEST(Abm3, ThirdOrderWithTheRungeKuttaStartOnDecayAndOscillator) {
  const double decay = measuredOrder(decayError, Abm3Params::Start::kRungeKutta3, "y' = -y, rk3");
  EXPECT_GT(decay, 2.7);
  EXPECT_LT(decay, 3.3);
  const double spring =
      measuredOrder(harmonicError, Abm3Params::Start::kRungeKutta3, "oscillator, rk3");
  EXPECT_GT(spring, 2.7);
  EXPECT_LT(spring, 3.3);
}

// The chapter's start (two forward-Euler steps) costs an order: its local error O(h^2) stays.
TEST(Abm3, SecondOrderWithTheForwardEulerStart) {
  const double decay = measuredOrder(decayError, Abm3Params::Start::kEuler, "y' = -y, euler");
  EXPECT_GT(decay, 1.7);
  EXPECT_LT(decay, 2.3);
  const double spring = measuredOrder(harmonicError, Abm3Params::Start::kEuler, "oscillator, euler");
  EXPECT_GT(spring, 1.7);
  EXPECT_LT(spring, 2.3);
}

TEST(Abm3, FixedStepHistoryCarriesOverFrames) {
  // Ten frames of 0.1 s give the same state as one frame of 1 s: the history survives.
  const Oscillators o = harmonic(0.0);
  System once = o.build(), framed = o.build();
  Abm3Integrator a(fixedStep(0.01, Abm3Params::Start::kRungeKutta3));
  Abm3Integrator b(fixedStep(0.01, Abm3Params::Start::kRungeKutta3));
  ASSERT_TRUE(a.advance(once, 1.0).ok);
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(b.advance(framed, 0.1).ok);
  EXPECT_EQ(a.startSteps(), 2);
  EXPECT_EQ(b.startSteps(), 2);
  EXPECT_LT((once.state.x - framed.state.x).lpNorm<Eigen::Infinity>(), 1e-12);
}

struct AdaptiveRun {
  std::vector<double> steps;  // the controller's next step after each frame
  std::vector<int> rejected;
  double maxError = 0.0;
};

// Frames of 0.01 s for `duration`; the error against the closed form after every frame.
AdaptiveRun runAdaptive(const Oscillators& o, const Eigen::VectorXd& damping,
                        const Abm3Params& params, double duration) {
  System s = o.build();
  s.damping = damping;
  Abm3Integrator integrator(params);
  AdaptiveRun run;
  const int frames = static_cast<int>(std::lround(duration / 0.01));
  for (int f = 0; f < frames; ++f) {
    const StepReport r = integrator.advance(s, 0.01);
    EXPECT_TRUE(r.ok) << r.failure;
    run.steps.push_back(integrator.stepControl().proposedStep());
    run.rejected.push_back(r.rejected);
    const Eigen::VectorXd u = s.state.x - restVector(s);
    for (int dof = 0; dof < 12; ++dof)
      run.maxError = std::max(run.maxError, std::abs(u[dof] - dampedExact(o.m, damping[dof], o.k[dof],
                                                                          o.u0[dof], o.v0[dof],
                                                                          s.state.t)));
  }
  return run;
}

Abm3Params adaptive(double initialStep, double absTol) {
  Abm3Params p;
  p.timeStep = initialStep;
  p.absTol = p.absTolVelocity = absTol;
  p.relTol = 0.0;
  return p;
}

TEST(Abm3, AdaptiveStepDoublesWhileTheMotionIsSmooth) {
  const Oscillators o = harmonic(0.0);
  const AdaptiveRun run =
      runAdaptive(o, Eigen::VectorXd::Zero(12), adaptive(1e-5, 1e-7), 0.5);
  std::printf("[ adaptive ] smooth: steps %.3g (frame 1) .. %.3g s (frame %zu), error %.3e\n",
              run.steps.front(), run.steps.back(), run.steps.size(), run.maxError);
  EXPECT_GE(run.steps.back(), 64 * 1e-5) << "at least six doublings";
  EXPECT_LT(run.maxError, 1e-5);
}

TEST(Abm3, AdaptiveStepHalvesOnAStiffTransientAndGrowsAfterIt) {
  // DOF 0: omega = 100 rad/s with damping ratio 0.5 (a transient gone after 0.2 s) beside the
  // period-1 s oscillators; a first step of 10 ms is far too long for it.
  Oscillators o = harmonic(0.0);
  o.k[0] = 1e4;
  Eigen::VectorXd damping = Eigen::VectorXd::Zero(12);
  damping[0] = 100.0;
  const AdaptiveRun run = runAdaptive(o, damping, adaptive(1e-2, 1e-6), 1.0);
  double shortest = 1e9;
  for (size_t f = 0; f < 10; ++f) shortest = std::min(shortest, run.steps[f]);
  double latest = 0.0;
  for (size_t f = 50; f < run.steps.size(); ++f) latest = std::max(latest, run.steps[f]);
  std::printf("[ adaptive ] stiff: rejected %d in frame 1, shortest step %.3g s in the first 10 "
              "frames, longest %.3g s after 0.5 s, error %.3e\n",
              run.rejected.front(), shortest, latest, run.maxError);
  EXPECT_GT(run.rejected.front(), 0);
  EXPECT_LE(shortest, 1e-2 / 8) << "at least three halvings";
  EXPECT_GE(latest, 4 * shortest) << "at least two doublings once the transient is gone";
  EXPECT_LT(run.maxError, 1e-4);
}

TEST(Abm3, HermiteHistoryInterpolationAlsoFollowsTheTransient) {
  Oscillators o = harmonic(0.0);
  o.k[0] = 1e4;
  Eigen::VectorXd damping = Eigen::VectorXd::Zero(12);
  damping[0] = 100.0;
  Abm3Params p = adaptive(1e-2, 1e-6);
  p.interpolation = Abm3Params::Interpolation::kHermite;
  const AdaptiveRun run = runAdaptive(o, damping, p, 1.0);
  std::printf("[ adaptive ] stiff, hermite history: error %.3e\n", run.maxError);
  EXPECT_LT(run.maxError, 1e-4);
}

TEST(Abm3, FixedNodesStayWhereTheyAre) {
  Oscillators o = harmonic(0.0);
  System s = o.build();
  s.mesh.nodeTags[1] = kFixedAll;
  s.updateConstraints();
  s.state.x.segment<3>(3) = s.mesh.rest.col(1);
  s.state.v.segment<3>(3).setZero();
  Abm3Integrator integrator(adaptive(1e-3, 1e-7));
  for (int f = 0; f < 20; ++f) ASSERT_TRUE(integrator.advance(s, 0.05).ok);
  EXPECT_EQ(Eigen::Vector3d(s.state.x.segment<3>(3)), Eigen::Vector3d(s.mesh.rest.col(1)));
  EXPECT_EQ(Eigen::Vector3d(s.state.v.segment<3>(3)), Eigen::Vector3d::Zero());
  const Eigen::VectorXd u = s.state.x - restVector(s);
  for (int dof : {0, 1, 2, 6, 7, 8, 9, 10, 11})
    EXPECT_NEAR(u[dof], o.exact(dof, s.state.t), 1e-5) << "free dof " << dof;
}

class Poison : public ForceModel {
 public:
  const char* name() const override { return "poison"; }
  double addForce(const Eigen::VectorXd&, const Eigen::VectorXd&,
                  Eigen::VectorXd& f) const override {
    if (active) f[4] = std::numeric_limits<double>::quiet_NaN();
    return 0.0;
  }
  double energy(const Eigen::VectorXd&) const override { return 0.0; }
  bool active = false;
};

TEST(Abm3, NonFiniteStateFailsTheFrameWithAReasonAndRestoresIt) {
  for (bool adaptiveStep : {false, true}) {
    System s = harmonic(0.0).build();
    auto poison = std::make_unique<Poison>();
    Poison* p = poison.get();
    s.models.push_back(std::move(poison));
    Abm3Params params = adaptive(1e-3, 1e-6);
    params.adaptive = adaptiveStep;
    Abm3Integrator integrator(params);
    ASSERT_TRUE(integrator.advance(s, 0.01).ok);
    const State before = s.state;
    p->active = true;
    const StepReport r = integrator.advance(s, 0.01);
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.failure.find("non-finite"), std::string::npos) << r.failure;
    EXPECT_EQ(s.state.x, before.x);
    EXPECT_EQ(s.state.v, before.v);
    EXPECT_EQ(s.state.t, before.t);
  }
}

// Every force model preset on a clamped block released from a shear: abm3 needs only forces.
TEST(Abm3, RunsWithEveryForceModel) {
  Mesh mesh = boxGrid(3, 3, 3, Eigen::Vector3d(0.02, 0.02, 0.02), TetSplit::kSixMirrored);
  mesh.fillDefaults();
  for (int n = 0; n < mesh.numNodes(); ++n)
    if (mesh.rest(2, n) < 1e-12) mesh.nodeTags[n] = kFixedAll;
  for (const std::string& preset : registry().modelPresetNames()) {
    System s(mesh, {Material::isotropic(3e3, 0.4, 1000.0)});
    s.models.push_back(makeElasticModel(preset, s.mesh, s.materials));
    s.damping = 5.0 * s.mass;
    s.updateConstraints();
    for (int n = 0; n < s.numNodes(); ++n) s.state.x[3 * n] += 0.05 * s.mesh.rest(2, n);
    Abm3Integrator integrator(adaptive(1e-4, 1e-7));
    double released = 0.0;
    for (int f = 0; f < 5; ++f) {
      const StepReport r = integrator.advance(s, 0.002);
      ASSERT_TRUE(r.ok) << preset << ": " << r.failure;
      EXPECT_GT(r.substeps, 0) << preset;
    }
    released = (s.state.x - s.mesh.rest.reshaped()).lpNorm<Eigen::Infinity>();
    EXPECT_TRUE(s.state.x.allFinite()) << preset;
    EXPECT_LT(released, 0.05 * 0.02 * 1.5) << preset << ": the shear must not grow";
  }
}

// ---------------------------------------------------------------------------------------
// Scene keys.

const char* const kAbm3Scene = R"(name: abm3_block
mesh:
  generator: box
  nodes: [3, 3, 3]
  size: [0.02, 0.02, 0.02]
materials:
  - young_modulus: 3
    stress_unit: kPa
    poisson_ratio: 0.4
    density: 1000
force_models:
  - type: tensor_mass
integrator:
  type: abm3
  KEYS
boundary:
  fixed:
    - plane: {point: [0, 0, 0], normal: [0, 0, 1]}
run: {frame_time: 0.01, duration: 0.05}
)";

std::string sceneWith(const std::string& keys) {
  std::string text = kAbm3Scene;
  return text.replace(text.find("KEYS"), 4, keys);
}

TEST(Abm3Scene, KeysReachTheIntegrator) {
  const std::string keys =
      "adaptive: true\n  time_step: 2e-4\n  start: euler\n  history_interpolation: hermite\n"
      "  abs_tol: 1e-5\n  abs_tol_velocity: 1e-3\n  rel_tol: 0\n  lower_ratio: 0.05\n"
      "  min_step: 1e-9\n  max_step: 1e-2";
  const Scene scene = loadScene(testutil::writeScene("abm3.yaml", sceneWith(keys)));
  const auto* abm = dynamic_cast<const Abm3Integrator*>(&unguarded(*scene.integrator));
  ASSERT_NE(abm, nullptr);
  const Abm3Params& p = abm->params();
  EXPECT_TRUE(p.adaptive);
  EXPECT_EQ(p.timeStep, 2e-4);
  EXPECT_EQ(p.start, Abm3Params::Start::kEuler);
  EXPECT_EQ(p.interpolation, Abm3Params::Interpolation::kHermite);
  EXPECT_EQ(p.absTol, 1e-5);
  EXPECT_EQ(p.absTolVelocity, 1e-3);
  EXPECT_EQ(p.relTol, 0.0);
  EXPECT_EQ(p.lowerRatio, 0.05);
  EXPECT_EQ(p.minStep, 1e-9);
  EXPECT_EQ(p.maxStep, 1e-2);
  const Scene defaults = loadScene(testutil::writeScene("abm3.yaml", sceneWith("")));
  const auto* d = dynamic_cast<const Abm3Integrator*>(&unguarded(*defaults.integrator));
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->params().start, Abm3Params::Start::kRungeKutta3);
  EXPECT_EQ(d->params().interpolation, Abm3Params::Interpolation::kLinear);
}

TEST(Abm3Scene, BadKeysGiveOneClearError) {
  using testutil::BadScene;
  const long line = 15;  // the KEYS line
  testutil::expectEachSceneFailsClearly(
      {{"unknown start", sceneWith("start: rk4"), line, "expected one of: rk3, euler"},
       {"unknown interpolation", sceneWith("history_interpolation: cubic"), line,
        "expected one of: linear, hermite"},
       {"negative tolerance", sceneWith("abs_tol: -1e-6"), line, "abs_tol"},
       {"negative relative tolerance", sceneWith("rel_tol: -1"), line, "non-negative"},
       {"lower ratio of 1", sceneWith("lower_ratio: 1"), line, "between 0 and 1"},
       {"max below min", sceneWith("min_step: 1e-3\n  max_step: 1e-4"), line + 1,
        "max_step >= min_step"},
       {"misspelt key", sceneWith("time_stpe: 1e-4"), line, "time_stpe"}},
      "bad_abm3.yaml");
}

}  // namespace
}  // namespace tt
