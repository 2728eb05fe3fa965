// The quasistatic equilibrium solve (solve/equilibrium.h) and the `quasistatic`
// integrator: Newton's quadratic convergence, the patch test, a contracting muscle against the
// one-element uniaxial answer of its law, a hanging box against backward Euler run to rest.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

#include "../model_test_util.h"
#include "../scene/scene_test_util.h"
#include "oscillators.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/gravity.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/solve/equilibrium.h"

namespace tt {
namespace {

// A soft neo-Hookean cantilever (2 kPa) bending under its own weight by about a fifth of its
// length: a markedly non-linear equilibrium.
std::unique_ptr<System> saggingBeam() {
  Mesh mesh = cantileverBeam(0.1, 0.02, 8, 2);
  auto s = std::make_unique<System>(mesh, std::vector<Material>{Material::isotropic(2e3, 0.3, 1000.0)});
  s->models.push_back(makeElasticModel("hyperelastic_neo_hookean", s->mesh, s->materials));
  s->models.push_back(std::make_unique<GravityModel>(s->mass, Eigen::Vector3d(0, 0, -9.81)));
  return s;
}

TEST(Equilibrium, NewtonConvergesQuadratically) {
  auto s = saggingBeam();
  EquilibriumParams p;
  p.preconditioner = EquilibriumParams::Preconditioning::kCholesky;
  p.linearTolerance = 1e-14;
  p.absoluteTolerance = 1e-13;
  p.relativeTolerance = 1e-15;
  const EquilibriumReport r = solveEquilibrium(*s, p);
  ASSERT_TRUE(r.converged()) << r.reason;
  const std::vector<double>& h = r.residualHistory;
  std::printf("residuals (N):");
  for (double v : h) std::printf(" %.3e", v);
  std::printf("\nr_k+1 / r_k^2:");
  for (size_t k = 0; k + 1 < h.size(); ++k) std::printf(" %.3g", h[k + 1] / (h[k] * h[k]));
  std::printf("\nnewton %d, cg %d, shifted %d, gradient %d\n", r.newtonIterations,
              r.linearIterations, r.shiftedSolves, r.gradientSteps);
  const double tip = s->state.x[s->numDofs() - 1] - s->mesh.rest(2, s->numNodes() - 1);
  EXPECT_LT(tip, -0.01) << "a large deflection";
  // Near the solution (r_k below 1e-2 r_0, r_k+1 a thousand times above the round-off floor
  // of about 1e-15 N) the ratio r_k+1 / r_k^2 stays bounded: at most ten times its first
  // value there (linear convergence would make it grow like 1 / r_k), and the last of these
  // steps gains more than four orders of magnitude.
  std::vector<double> ratios;
  size_t last = 0;
  for (size_t k = 0; k + 1 < h.size(); ++k)
    if (h[k] < 1e-2 * h[0] && h[k + 1] > 1e-12) {
      ratios.push_back(h[k + 1] / (h[k] * h[k]));
      last = k;
    }
  ASSERT_GE(ratios.size(), 2u) << "too few iterations near the solution";
  for (double ratio : ratios) EXPECT_LT(ratio, 10.0 * ratios.front());
  EXPECT_LT(h[last + 1], 1e-4 * h[last]);
  // Far from the solution the stiffness is indefinite (CG met non-positive curvature and
  // the Cholesky factorisation was refused): the shifted solves took those steps.
  EXPECT_GT(r.shiftedSolves, 0);
  EXPECT_EQ(r.gradientSteps, 0);
  EXPECT_LT(r.residual, 1e-13);
  EXPECT_EQ(s->state.v.norm(), 0.0);
}

// A jittered box of tets whose boundary nodes follow x = G X + t: every interior node lands
// on the same map (a homogeneous deformation is an exact equilibrium of linear tets).
// Stiff, nearly incompressible tissue (1 GPa, nu 0.4999): the round-off of its residual is
// far above any tolerance in newtons. Asked for an unreachable 1e-30 N, the solve stops as
// converged once Newton's step is at the round-off of the positions, at the equilibrium of
// a tolerance it can meet; a second solve from there stops at once.
TEST(Equilibrium, StopsAtTheRoundOffOfStiffTissue) {
  Mesh mesh = cantileverBeam(0.1, 0.02, 8, 2);
  System stiff(mesh, std::vector<Material>{Material::isotropic(1e9, 0.4999, 1000.0)});
  stiff.models.push_back(makeElasticModel("hyperelastic_neo_hookean", stiff.mesh, stiff.materials));
  stiff.models.push_back(std::make_unique<GravityModel>(stiff.mass, Eigen::Vector3d(0, 0, -9.81)));
  const Eigen::VectorXd rest = stiff.state.x;
  EquilibriumParams reachable;
  reachable.preconditioner = EquilibriumParams::Preconditioning::kCholesky;
  reachable.linearTolerance = 1e-14;
  reachable.absoluteTolerance = 1e-6;
  reachable.relativeTolerance = 0.0;
  const EquilibriumReport first = solveEquilibrium(stiff, reachable);
  ASSERT_TRUE(first.converged()) << first.reason;
  EXPECT_FALSE(first.atRoundOff);
  const Eigen::VectorXd reference = stiff.state.x;

  EquilibriumParams unreachable = reachable;
  unreachable.absoluteTolerance = 1e-30;
  stiff.state.x = rest;
  const EquilibriumReport r = solveEquilibrium(stiff, unreachable);
  std::printf("round-off stop: %d Newton iterations, residual %.3e N (from %.3e N)\n",
              r.newtonIterations, r.residual, r.initialResidual);
  ASSERT_TRUE(r.converged()) << r.reason;
  EXPECT_TRUE(r.atRoundOff);
  EXPECT_LT(r.residual, 1e-4 * r.initialResidual);
  EXPECT_LT(r.newtonIterations, unreachable.maxNewtonIterations);
  EXPECT_LT((stiff.state.x - reference).lpNorm<Eigen::Infinity>(), 1e-12);

  const EquilibriumReport again = solveEquilibrium(stiff, unreachable);
  ASSERT_TRUE(again.converged()) << again.reason;
  EXPECT_TRUE(again.atRoundOff);
  EXPECT_LE(again.newtonIterations, 1);
}

TEST(Equilibrium, PatchTestPutsInteriorNodesOnTheAffineMap) {
  std::mt19937 rng(7);
  const int c = 3;
  Mesh mesh = testutil::boxMesh(c, c, c, 0.01, rng, 0.15);
  for (auto& m : mesh.material) m = 0;
  System s(mesh, {Material::isotropic(1e4, 0.35, 1000.0)});
  s.models.push_back(makeElasticModel("hyperelastic_neo_hookean", s.mesh, s.materials));
  Eigen::Matrix3d G;
  G << 1.15, 0.08, -0.03, 0.02, 0.92, 0.06, -0.05, 0.04, 1.07;
  const Eigen::Vector3d t(0.001, -0.002, 0.0005);
  const auto affine = [&](int n) { return Eigen::Vector3d(G * s.mesh.rest.col(n) + t); };
  std::vector<int> interior;
  for (int k = 0; k <= c; ++k)
    for (int j = 0; j <= c; ++j)
      for (int i = 0; i <= c; ++i) {
        const int n = i + (c + 1) * (j + (c + 1) * k);
        const bool boundary = i == 0 || j == 0 || k == 0 || i == c || j == c || k == c;
        if (boundary) s.mesh.nodeTags[n] = kFixedAll;
        else interior.push_back(n);
      }
  s.updateConstraints();
  ASSERT_EQ(interior.size(), 8u);
  Eigen::VectorXd x = s.state.x;
  for (int n = 0; n < s.numNodes(); ++n)
    if (s.mesh.nodeTags[n]) x.segment<3>(3 * n) = affine(n);
  EquilibriumSolver solver;
  const EquilibriumReport r = solver.solve(s, x);
  ASSERT_TRUE(r.converged()) << r.reason;
  EXPECT_GT(r.newtonIterations, 1);
  for (int n : interior)
    EXPECT_LT((x.segment<3>(3 * n) - affine(n)).norm(), 1e-10) << "node " << n;
}

// Bisection for g(v) = 0 on [lo, hi] (g changes sign there).
double bisect(const std::function<double(double)>& g, double lo, double hi) {
  double glo = g(lo);
  EXPECT_LT(glo * g(hi), 0.0) << "no sign change on [" << lo << ", " << hi << "]";
  for (int k = 0; k < 200 && hi - lo > 1e-15; ++k) {
    const double mid = 0.5 * (lo + hi), gm = g(mid);
    if ((gm < 0.0) == (glo < 0.0)) {
      lo = mid;
      glo = gm;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

// A muscle block (fibre along x, alpha = 0.5) on a sliding clamp at x = 0 and free elsewhere
// contracts homogeneously: F = diag(lam, mu, mu), with P_22(lam, mu) = 0 (free lateral
// faces) and P_11(lam, mu) = 0 (free end). The answer comes from the law's stress by nested
// bisection, not from the solver.
TEST(Equilibrium, ActivatedMuscleContractsToItsUniaxialLength) {
  TeranMuscleLaw::Constants k;  // PhysBAM's constants, deviatoric fibre stretch
  k.activation = 0.5;
  const TeranMuscleLaw::Parameters law = TeranMuscleLaw::parameters(k, Eigen::Matrix3d::Identity());
  const auto P = [&](double lam, double mu) {
    return TeranMuscleLaw::stress(law, Eigen::Vector3d(lam, mu, mu).asDiagonal());
  };
  const auto lateral = [&](double lam) {
    return bisect([&](double mu) { return P(lam, mu)(1, 1); }, 0.5, 2.0);
  };
  const double lam = bisect([&](double l) { return P(l, lateral(l))(0, 0); }, 0.6, 1.0);
  const double mu = lateral(lam);
  std::printf("uniaxial answer: lam = %.12f, mu = %.12f\n", lam, mu);
  ASSERT_LT(lam, 0.95) << "the activated fibre contracts";

  const Eigen::Vector3d size(0.03, 0.01, 0.01);
  Mesh mesh = boxGrid(5, 3, 3, size, TetSplit::kFiveMirrored);
  System s(mesh, {Material::isotropic(1e5, 0.3, 1000.0)});
  s.models.push_back(std::make_unique<HyperelasticModel<TeranMuscleLaw>>(
      s.mesh, std::vector<TeranMuscleLaw::Constants>{k}, LawOptions{}));
  for (int n = 0; n < s.numNodes(); ++n) {
    const Eigen::Vector3d X = s.mesh.rest.col(n);
    if (X.x() != 0.0) continue;
    s.mesh.nodeTags[n] = kFixedX;                                 // sliding clamp
    if (X.y() == 0.0 && X.z() == 0.0) s.mesh.nodeTags[n] = kFixedAll;  // no translation
    if (X.y() == size.y() && X.z() == 0.0) s.mesh.nodeTags[n] |= kFixedZ;  // no spin about x
  }
  s.updateConstraints();
  const EquilibriumReport r = solveEquilibrium(s);
  ASSERT_TRUE(r.converged()) << r.reason;
  std::printf("newton %d, cg %d, shifted %d, gradient %d, residual %.3g N\n", r.newtonIterations,
              r.linearIterations, r.shiftedSolves, r.gradientSteps, r.residual);
  const Eigen::Vector3d stretches(lam, mu, mu);
  for (int n = 0; n < s.numNodes(); ++n)
    EXPECT_LT((s.state.x.segment<3>(3 * n) - stretches.cwiseProduct(s.mesh.rest.col(n))).norm(),
              1e-9)
        << "node " << n;
  double length = 0.0;
  for (int n = 0; n < s.numNodes(); ++n) length = std::max(length, s.state.x[3 * n]);
  EXPECT_NEAR(length, lam * size.x(), 1e-10);
}

const char* const kHangingScene = R"(name: hanging
mesh: {generator: box, nodes: [3, 3, 5], size: [0.02, 0.02, 0.04]}
materials:
  - {young_modulus: 20, poisson_ratio: 0.3, stress_unit: kPa, density: 1000}
force_models:
  - {type: hyperelastic, law: neo_hookean}
integrator: {type: quasistatic}
boundary:
  fixed:
    - plane: {point: [0, 0, 0.04], normal: [0, 0, 1]}
loads:
  gravity: [0, 0, -9.81]
  rayleigh_mass: 20
run: {frame_time: 0.01, duration: 3}
)";

// A force that is NaN at its own equilibrium (as a law at a pole would be), reached by a Newton
// step at the round-off of the positions: the solve must end as non-finite, not as converged
// (a NaN residual is not above any tolerance).
class NanAtRest : public oscillators::DofPotential {
 public:
  NanAtRest(Eigen::VectorXd k, const Eigen::VectorXd& rest)
      : DofPotential(std::move(k), rest), rest_(rest) {}
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override {
    if (!atRest(x)) return DofPotential::addForce(x, v, f);
    f.setConstant(std::nan(""));
    return std::nan("");
  }
  double energy(const Eigen::VectorXd& x) const override {
    return atRest(x) ? std::nan("") : DofPotential::energy(x);
  }

 private:
  bool atRest(const Eigen::VectorXd& x) const { return (x - rest_).cwiseAbs().maxCoeff() < 5e-16; }
  Eigen::VectorXd rest_;
};

TEST(Equilibrium, ANonFiniteForceAtTheEndIsNoEquilibrium) {
  System s(oscillators::unitTet(), {Material::isotropic(1e3, 0.3, 1000.0)});
  const Eigen::VectorXd rest = oscillators::restVector(s);
  s.models.push_back(
      std::make_unique<NanAtRest>(Eigen::VectorXd::Constant(rest.size(), 1e9), rest));
  Eigen::VectorXd x = rest.array() + 2e-15;  // a residual of 2e-6 N, a step at the round-off
  EquilibriumParams p;
  p.absoluteTolerance = 1e-9;
  p.relativeTolerance = 0.0;
  EquilibriumSolver solver(p);
  const EquilibriumReport r = solver.solve(s, x);
  EXPECT_FALSE(r.converged()) << "residual " << r.residual;
  EXPECT_EQ(r.stop, EquilibriumStop::kNonFiniteForce) << r.reason;
}

// The quasistatic frame lands where a damped backward-Euler run comes to rest.
TEST(QuasistaticIntegrator, HangingBoxMatchesBackwardEulerAtRest) {
  Scene quasi = loadScene(testutil::writeScene("hanging_qs.yaml", kHangingScene));
  const StepReport r = quasi.integrator->advance(quasi.system, quasi.frameTime);
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_GT(r.newtonIterations, 0);
  EXPECT_GT(r.linearIterations, 0);
  EXPECT_EQ(quasi.system.state.v.norm(), 0.0);
  // A second frame starts at the equilibrium: nothing to do.
  const StepReport again = quasi.integrator->advance(quasi.system, quasi.frameTime);
  ASSERT_TRUE(again.ok) << again.failure;
  EXPECT_EQ(again.newtonIterations, 0);

  Scene dynamic = loadScene(testutil::writeScene(
      "hanging_be.yaml", testutil::replaced(kHangingScene, "{type: quasistatic}",
                                            "{type: backward_euler, linear_tolerance: 1e-12}")));
  for (int frame = 0; frame < 300; ++frame) {
    const StepReport step = dynamic.integrator->advance(dynamic.system, dynamic.frameTime);
    ASSERT_TRUE(step.ok) << step.failure;
  }
  const Eigen::VectorXd rest = Eigen::Map<const Eigen::VectorXd>(
      quasi.system.mesh.rest.data(), quasi.system.numDofs());
  const double sag = (quasi.system.state.x - rest).lpNorm<Eigen::Infinity>();
  const double difference = (quasi.system.state.x - dynamic.system.state.x).lpNorm<Eigen::Infinity>();
  std::printf("sag %.6g m, |x_qs - x_be| %.3g m, be kinetic %.3g J\n", sag, difference,
              dynamic.system.kineticEnergy(dynamic.system.state.v));
  EXPECT_GT(sag, 1e-4);
  EXPECT_LT(difference, 1e-6 * sag);
}

// A frame that cannot converge in the allowed iterations fails with the solver's reason and
// leaves the state as it was.
TEST(QuasistaticIntegrator, UnconvergedFrameFailsCleanly) {
  Scene scene = loadScene(testutil::writeScene(
      "hanging_one.yaml",
      testutil::replaced(kHangingScene, "{type: quasistatic}",
                         "{type: quasistatic, max_newton_iterations: 1}") +
          "stability_guard: {enabled: false}\n"));
  const Eigen::VectorXd before = scene.system.state.x;
  const StepReport r = scene.integrator->advance(scene.system, scene.frameTime);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("no convergence in 1 Newton iterations"), std::string::npos)
      << r.failure;
  EXPECT_EQ(scene.system.state.x, before);
}

// Each frame puts the controlled face where its path is at the frame's end and the free
// nodes in equilibrium there.
TEST(QuasistaticIntegrator, ControlledFaceFollowsItsPathFrameByFrame) {
  Scene scene = loadScene(testutil::writeScene("sheared_block.yaml", R"(name: sheared
mesh: {generator: box, nodes: [3, 3, 3], size: [0.01, 0.01, 0.01]}
materials:
  - {young_modulus: 10, poisson_ratio: 0.4, stress_unit: kPa}
force_models:
  - {type: hyperelastic, law: neo_hookean}
integrator: {type: quasistatic, newton_abs_tolerance: 1e-10}
boundary:
  fixed:
    - plane: {point: [0, 0, 0], normal: [0, 0, 1]}
  controlled:
    - plane: {point: [0, 0, 0.01], normal: [0, 0, 1]}
      path: [[0, 0, 0, 0], [1, 0.002, 0, 0.001]]
run: {frame_time: 0.25, duration: 1}
)"));
  System& s = scene.system;
  ASSERT_EQ(s.controlled.size(), 1u);
  Eigen::VectorXd f;
  for (int frame = 1; frame <= 4; ++frame) {
    const StepReport r = scene.integrator->advance(s, scene.frameTime);
    ASSERT_TRUE(r.ok) << r.failure;
    EXPECT_DOUBLE_EQ(s.state.t, 0.25 * frame);
    const Eigen::Vector3d offset = Eigen::Vector3d(0.002, 0, 0.001) * 0.25 * frame;
    for (int n : s.controlled[0].nodes)
      EXPECT_LT((s.state.x.segment<3>(3 * n) - s.mesh.rest.col(n) - offset).norm(), 1e-15);
    s.computeForce(s.state.x, s.state.v, f);
    s.zeroConstrained(f);
    EXPECT_LE(f.norm(), 1e-10) << "frame " << frame;
    EXPECT_GT(r.newtonIterations, 0);
  }
}

}  // namespace
}  // namespace tt
