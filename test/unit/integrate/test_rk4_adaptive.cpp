// The classical Runge-Kutta method with step doubling (integrate/rk4_adaptive.h): its order at
// fixed step, the doubling error estimate, the adaptive error and cost against the tolerance,
// the stable step on a tissue beam beside explicit Euler's (the claim of "A non-linear
// anisotropic Finite Element Method for surgical simulation", Appendix A), fixed nodes, the
// per-frame step limit and the scene keys.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include "../scene/scene_test_util.h"
#include "oscillators.h"
#include "tissue_trainer/core/integrate/explicit_euler.h"
#include "tissue_trainer/core/integrate/rk4_adaptive.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace {

using namespace oscillators;

Rk4AdaptiveParams fixedStep(double h) {
  Rk4AdaptiveParams p;
  p.adaptive = false;
  p.timeStep = h;
  return p;
}

Rk4AdaptiveParams tolerance(double tol, bool extrapolate = true) {
  Rk4AdaptiveParams p;
  p.timeStep = 1e-3;
  p.absTol = p.absTolVelocity = tol;
  p.relTol = 0.0;
  p.extrapolate = extrapolate;
  return p;
}

// Position and velocity of DOF `dof` of the undamped oscillators at t.
Eigen::Vector2d undampedExact(const Oscillators& o, int dof, double t) {
  const double w = std::sqrt(o.k[dof] / o.m), A = o.u0[dof], B = o.v0[dof] / w;
  return {A * std::cos(w * t) + B * std::sin(w * t), w * (B * std::cos(w * t) - A * std::sin(w * t))};
}

double stateError(const Oscillators& o, const System& s) {
  double e = 0.0;
  const Eigen::VectorXd u = s.state.x - restVector(s);
  for (int dof = 0; dof < u.size(); ++dof) {
    const Eigen::Vector2d exact = undampedExact(o, dof, s.state.t);
    e = std::max({e, std::abs(u[dof] - exact[0]), std::abs(s.state.v[dof] - exact[1])});
  }
  return e;
}

TEST(Rk4Adaptive, FixedStepIsFourthOrderOnUndampedAndDampedOscillators) {
  for (double damping : {0.0, 0.5}) {
    const Oscillators o = harmonic(damping);
    std::vector<double> hs, errs;
    // From 80 steps on the error ratio per halving is within 5 % of 16 (at 10-40 steps the damped
    // case is not yet asymptotic: ratios 6 and 12).
    for (int n : {80, 160, 320, 640}) {
      System s = o.build();
      Rk4AdaptiveIntegrator integrator(fixedStep(1.0 / n));
      const StepReport r = integrator.advance(s, 1.0);
      ASSERT_TRUE(r.ok) << r.failure;
      EXPECT_EQ(r.substeps, n);
      EXPECT_EQ(integrator.forceEvaluations(), 4L * n);
      hs.push_back(1.0 / n);
      errs.push_back(o.maxError(s));
    }
    const double slope = logSlope(hs, errs);
    std::printf("[ order    ] rk4 c = %.1f: errors %.3e %.3e %.3e %.3e at h = 1/80 .. 1/640, "
                "slope %.3f\n", damping, errs[0], errs[1], errs[2], errs[3], slope);
    EXPECT_GT(slope, 3.8);
    EXPECT_LT(slope, 4.2);
  }
}

// One doubled step without extrapolation: (y_two - y_big) / 15 is y_two's actual error.
TEST(Rk4Adaptive, DoublingEstimateMatchesTheActualErrorOfTheTwoHalfSteps) {
  const Oscillators o = harmonic(0.0);
  for (double h : {0.1, 0.05, 0.025}) {
    System s = o.build();
    Rk4AdaptiveParams p = tolerance(1.0, false);  // unit weights: the error is the raw one
    p.timeStep = h;
    p.maxStep = h;
    Rk4AdaptiveIntegrator integrator(p);
    const StepReport r = integrator.advance(s, h);
    ASSERT_TRUE(r.ok) << r.failure;
    ASSERT_EQ(r.substeps, 1);
    EXPECT_EQ(integrator.forceEvaluations(), 11);
    const double actual = stateError(o, s);
    std::printf("[ estimate ] h = %.3f: estimate %.4e, actual %.4e, ratio %.3f\n", h,
                r.errorEstimate, actual, r.errorEstimate / actual);
    EXPECT_GT(r.errorEstimate / actual, 0.8);
    EXPECT_LT(r.errorEstimate / actual, 1.25);
  }
}

struct TolerancedRun {
  int steps = 0, rejected = 0;
  double maxError = 0.0;  // positions and velocities against the closed form, every frame
};

TolerancedRun runToTolerance(const Oscillators& o, const Rk4AdaptiveParams& p) {
  System s = o.build();
  Rk4AdaptiveIntegrator integrator(p);
  TolerancedRun run;
  for (int f = 0; f < 10; ++f) {
    const StepReport r = integrator.advance(s, 0.2);
    EXPECT_TRUE(r.ok) << r.failure;
    run.steps += r.substeps;
    run.rejected += r.rejected;
    run.maxError = std::max(run.maxError, stateError(o, s));
  }
  return run;
}

// Two seconds of the period-1 s oscillators: the step count follows tol^(-1/5) (the local
// error of the two half steps scales as h^5). The control is per step, so without
// extrapolation the global error is about the sum of the local ones, up to steps x tol; with
// it each step's error is a factor of order h omega below tol and the sum stays a few tol.
TEST(Rk4Adaptive, ErrorFollowsTheToleranceAndStepsGrowAsTolToTheMinusOneFifth) {
  const Oscillators o = harmonic(0.0);
  for (bool extrapolate : {true, false}) {
    std::vector<double> tols, steps;
    for (double tol : {1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10}) {
      const TolerancedRun run = runToTolerance(o, tolerance(tol, extrapolate));
      std::printf("[ tolerance] extrapolate %d, tol %.0e: %d steps (%d rejected), error %.3e "
                  "= %.3f tol\n", extrapolate, tol, run.steps, run.rejected, run.maxError,
                  run.maxError / tol);
      EXPECT_LT(run.maxError, extrapolate ? 10.0 * tol : 1.5 * run.steps * tol) << tol;
      tols.push_back(tol);
      steps.push_back(run.steps);
    }
    const double slope = logSlope(tols, steps);
    std::printf("[ tolerance] extrapolate %d: steps ~ tol^%.3f\n", extrapolate, slope);
    EXPECT_GT(slope, -0.23);
    EXPECT_LT(slope, -0.17);
  }
}

// ---------------------------------------------------------------------------------------
// A stiff case: a soft tissue beam (8 x 2 x 2 cells, 10 x 2 x 2 cm, E = 5 kPa, edge-length
// StVK), clamped at one end, mass damping alpha = 0.1 omega_max (damping ratio 0.05 in the
// fastest mode). Forward Euler is stable only for h <= alpha / omega^2 in every mode
// (|1 + h lambda| <= 1), here 0.1 / omega_max; RK4's region reaches about 2.8 along the
// imaginary axis (2.91 at this damping ratio). Per force evaluation (1 for Euler, 4 for RK4)
// RK4 takes the longer step.

struct TissueBeam {
  std::unique_ptr<System> system;
  double omegaMax = 0.0;
  Eigen::VectorXd start;  // rest plus a small random displacement of the free nodes
};

double omegaMaxOf(System& s) {
  SparseMatrix K;
  s.assembleStiffness(s.mesh.rest.reshaped(), K);
  const Eigen::VectorXd scale = s.mass.cwiseSqrt().cwiseInverse();
  Eigen::MatrixXd A = -(scale.asDiagonal() * Eigen::MatrixXd(K) * scale.asDiagonal());
  for (int dof : s.constrainedDofs) {
    A.row(dof).setZero();
    A.col(dof).setZero();
  }
  return std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A, Eigen::EigenvaluesOnly)
                       .eigenvalues()
                       .maxCoeff());
}

TissueBeam tissueBeam() {
  TissueBeam b;
  b.system = std::make_unique<System>(cantileverBeam(0.1, 0.02, 8, 2),
                                      std::vector<Material>{Material::isotropic(5e3, 0.4, 1000.0)});
  System& s = *b.system;
  s.models.push_back(std::make_unique<EdgeLengthModel>(s.mesh, s.materials));
  b.omegaMax = omegaMaxOf(s);
  s.damping = 0.1 * b.omegaMax * s.mass;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-1e-5, 1e-5);
  b.start = s.mesh.rest.reshaped();
  for (Eigen::Index i = 0; i < b.start.size(); ++i)
    if (!s.isConstrained[i]) b.start[i] += jitter(rng);
  return b;
}

double energy(const System& s) {
  return s.potentialEnergy(s.state.x) - s.potentialEnergy(s.mesh.rest.reshaped()) +
         s.kineticEnergy(s.state.v);
}

// `steps` steps of h from the displaced beam: stable when the energy did not grow (the damped
// exact motion only loses energy; an unstable mode grows by orders of magnitude).
bool staysStable(TissueBeam& b, Integrator& integrator, double h, int steps) {
  System& s = *b.system;
  s.state.x = b.start;
  s.state.v.setZero();
  s.state.t = 0.0;
  const double e0 = energy(s);
  for (int i = 0; i < steps; ++i)
    if (!integrator.advance(s, h).ok) return false;
  return energy(s) <= e0;
}

// The largest stable step between lo (stable) and hi (unstable), to 1 % by bisection in log h.
// Just past the limit the fastest mode grows slowly (Euler: by 1 + 0.01 d (1 + d) per step at
// (1 + d) times the limit), hence many steps.
template <class Make>
double stableLimit(TissueBeam& b, Make make, double lo, double hi, int steps) {
  EXPECT_TRUE(staysStable(b, *make(lo), lo, steps)) << "lower bracket " << lo;
  EXPECT_FALSE(staysStable(b, *make(hi), hi, steps)) << "upper bracket " << hi;
  while (hi / lo > 1.01) {
    const double mid = std::sqrt(lo * hi);
    (staysStable(b, *make(mid), mid, steps) ? lo : hi) = mid;
  }
  return lo;
}

TEST(Rk4Adaptive, TakesALongerStableStepThanExplicitEulerForTheSameForceEvaluations) {
  TissueBeam b = tissueBeam();
  const double w = b.omegaMax;
  const double euler = stableLimit(
      b, [](double h) { return std::make_unique<ExplicitEulerIntegrator>(ExplicitEulerParams{h}); },
      0.01 / w, 1.0 / w, 10000);
  const double rk4 = stableLimit(
      b, [](double h) { return std::make_unique<Rk4AdaptiveIntegrator>(fixedStep(h)); }, 1.0 / w,
      5.0 / w, 3000);
  std::printf("[ stiff    ] beam omega_max %.1f rad/s: explicit Euler stable to h = %.4g s "
              "(%.4f / omega_max, theory 0.1), RK4 to %.4g s (%.3f / omega_max, theory 2.91), per force "
              "evaluation %.4g s, %.2f x Euler's\n",
              w, euler, euler * w, rk4, rk4 * w, rk4 / 4.0, rk4 / 4.0 / euler);
  // Predicted: |1 + z| = 1 at h omega = 0.1; |R(z)| = 1 for RK4's polynomial R at
  // h omega = 2.91 (lambda = omega (-0.05 + 0.9987 i)).
  EXPECT_NEAR(euler * w, 0.1, 0.015) << "the measured Euler limit is the predicted one";
  EXPECT_NEAR(rk4 * w, 2.91, 0.1) << "the measured RK4 limit is the predicted one";
  EXPECT_GT(rk4 / 4.0, 3.0 * euler) << "RK4's step per force evaluation";

  // The adaptive method on the same beam over 20 ms, tolerances a tenth of the initial
  // displacement (and of omega_max times it): its step settles near the stability limit, where
  // it stays stable with fewer force evaluations than Euler at Euler's own limit.
  System& s = *b.system;
  s.state.x = b.start;
  s.state.v.setZero();
  s.state.t = 0.0;
  const double e0 = energy(s);
  Rk4AdaptiveParams p = tolerance(1e-6);
  p.absTolVelocity = 1e-6 * w;
  Rk4AdaptiveIntegrator adaptive(p);
  int steps = 0;
  for (int f = 0; f < 4; ++f) {  // frames of 5 ms: longer than any stable step
    const StepReport r = adaptive.advance(s, 5e-3);
    ASSERT_TRUE(r.ok) << r.failure;
    steps += r.substeps;
  }
  const double eulerEvaluations = 0.02 / euler;
  std::printf("[ stiff    ] rk4_adaptive, abs_tol 1e-6 m: %d steps, %ld force evaluations in "
              "20 ms (mean step %.4g s = %.3f / omega_max); explicit Euler at its limit: %.0f\n",
              steps, adaptive.forceEvaluations(), 0.02 / steps, 0.02 / steps * w,
              eulerEvaluations);
  EXPECT_LE(energy(s), e0);
  EXPECT_LT(adaptive.forceEvaluations(), eulerEvaluations);
}

// ---------------------------------------------------------------------------------------

TEST(Rk4Adaptive, FixedNodesStayWhereTheyAre) {
  for (bool adaptiveStep : {true, false}) {
    Oscillators o = harmonic(0.0);
    System s = o.build();
    s.mesh.nodeTags[1] = kFixedAll;
    s.updateConstraints();
    s.state.x.segment<3>(3) = s.mesh.rest.col(1);
    s.state.v.segment<3>(3).setZero();
    Rk4AdaptiveParams p = adaptiveStep ? tolerance(1e-8) : fixedStep(1e-2);
    Rk4AdaptiveIntegrator integrator(p);
    for (int f = 0; f < 20; ++f) ASSERT_TRUE(integrator.advance(s, 0.05).ok);
    EXPECT_EQ(Eigen::Vector3d(s.state.x.segment<3>(3)), Eigen::Vector3d(s.mesh.rest.col(1)));
    EXPECT_EQ(Eigen::Vector3d(s.state.v.segment<3>(3)), Eigen::Vector3d::Zero());
    const Eigen::VectorXd u = s.state.x - restVector(s);
    for (int dof : {0, 1, 2, 6, 7, 8, 9, 10, 11})
      EXPECT_NEAR(u[dof], o.exact(dof, s.state.t), 1e-6) << "free dof " << dof;
  }
}

TEST(Rk4Adaptive, AFrameOverTheStepLimitFailsWithAMessageAndRestoresTheState) {
  const Oscillators o = harmonic(0.0);
  System s = o.build();
  const State before = s.state;
  Rk4AdaptiveParams p = tolerance(1e-15);
  p.maxSubsteps = 50;
  Rk4AdaptiveIntegrator adaptive(p);
  StepReport r = adaptive.advance(s, 1.0);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("more than 50 steps"), std::string::npos) << r.failure;
  EXPECT_NE(r.failure.find("max_substeps"), std::string::npos) << r.failure;
  EXPECT_LE(adaptive.forceEvaluations(), 11 * 50);
  EXPECT_EQ(s.state.x, before.x);
  EXPECT_EQ(s.state.t, before.t);

  Rk4AdaptiveParams fixed = fixedStep(1e-6);
  fixed.maxSubsteps = 1000;
  Rk4AdaptiveIntegrator tooFine(fixed);
  r = tooFine.advance(s, 1.0);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("max_substeps"), std::string::npos) << r.failure;
  EXPECT_EQ(tooFine.forceEvaluations(), 0) << "refused before any step";

  Rk4AdaptiveParams floor = tolerance(1e-15);
  floor.minStep = 1e-3;
  Rk4AdaptiveIntegrator underflow(floor);
  r = underflow.advance(s, 1.0);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("step size underflow"), std::string::npos) << r.failure;
  EXPECT_EQ(s.state.x, before.x);
}

TEST(Rk4Adaptive, RejectsParametersOutsideTheirRanges) {
  Rk4AdaptiveParams p;
  p.absTol = 0.0;
  EXPECT_THROW(Rk4AdaptiveIntegrator{p}, std::invalid_argument);
  p = {};
  p.relTol = -1.0;
  EXPECT_THROW(Rk4AdaptiveIntegrator{p}, std::invalid_argument);
  p = {};
  p.maxSubsteps = 0;
  EXPECT_THROW(Rk4AdaptiveIntegrator{p}, std::invalid_argument);
  p = {};
  p.minStep = 1e-3;
  p.maxStep = 1e-4;
  EXPECT_THROW(Rk4AdaptiveIntegrator{p}, std::invalid_argument);
}

// ---------------------------------------------------------------------------------------
// Scene keys.

const char* const kScene = R"(name: rk4_block
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
  type: rk4_adaptive
  KEYS
boundary:
  fixed:
    - plane: {point: [0, 0, 0], normal: [0, 0, 1]}
run: {frame_time: 0.01, duration: 0.05}
)";

std::string sceneWith(const std::string& keys) { return testutil::replaced(kScene, "KEYS", keys); }

TEST(Rk4AdaptiveScene, KeysReachTheIntegrator) {
  const std::string keys =
      "adaptive: false\n  time_step: 2e-4\n  abs_tol: 1e-5\n  abs_tol_velocity: 1e-3\n"
      "  rel_tol: 0\n  extrapolate: false\n  min_step: 1e-9\n  max_step: 1e-2\n"
      "  max_substeps: 500";
  const Scene scene = loadScene(testutil::writeScene("rk4.yaml", sceneWith(keys)));
  const auto* rk4 = dynamic_cast<const Rk4AdaptiveIntegrator*>(&unguarded(*scene.integrator));
  ASSERT_NE(rk4, nullptr);
  const Rk4AdaptiveParams& p = rk4->params();
  EXPECT_FALSE(p.adaptive);
  EXPECT_EQ(p.timeStep, 2e-4);
  EXPECT_EQ(p.absTol, 1e-5);
  EXPECT_EQ(p.absTolVelocity, 1e-3);
  EXPECT_EQ(p.relTol, 0.0);
  EXPECT_FALSE(p.extrapolate);
  EXPECT_EQ(p.minStep, 1e-9);
  EXPECT_EQ(p.maxStep, 1e-2);
  EXPECT_EQ(p.maxSubsteps, 500);
  const Scene defaults = loadScene(testutil::writeScene("rk4.yaml", sceneWith("")));
  const auto* d = dynamic_cast<const Rk4AdaptiveIntegrator*>(&unguarded(*defaults.integrator));
  ASSERT_NE(d, nullptr);
  EXPECT_TRUE(d->params().adaptive);
  EXPECT_TRUE(d->params().extrapolate);
  EXPECT_EQ(d->params().absTolVelocity, d->params().absTol);
}

TEST(Rk4AdaptiveScene, BadKeysGiveOneClearError) {
  const long line = 15;  // the KEYS line
  testutil::expectEachSceneFailsClearly(
      {{"zero tolerance", sceneWith("abs_tol: 0"), line, "abs_tol"},
       {"negative velocity tolerance", sceneWith("abs_tol_velocity: -1"), line,
        "abs_tol_velocity"},
       {"negative relative tolerance", sceneWith("rel_tol: -1e-6"), line, "non-negative"},
       {"text step", sceneWith("time_step: short"), line, "time_step"},
       {"extrapolate not a boolean", sceneWith("extrapolate: maybe"), line, "extrapolate"},
       {"zero substeps", sceneWith("max_substeps: 0"), line, "max_substeps"},
       {"fractional substeps", sceneWith("max_substeps: 2.5"), line, "max_substeps"},
       {"max below min", sceneWith("min_step: 1e-3\n  max_step: 1e-4"), line + 1,
        "max_step >= min_step"},
       {"a key of abm3", sceneWith("lower_ratio: 0.1"), line, "lower_ratio"},
       {"misspelt key", sceneWith("abs_tols: 1e-6"), line, "abs_tols"}},
      "bad_rk4_adaptive.yaml");
}

}  // namespace
}  // namespace tt
