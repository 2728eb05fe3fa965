#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <memory>

#include "oscillators.h"
#include "tissue_trainer/core/integrate/radau_iia.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace {

// Test-only springs: every node tied to its rest position (stiffness `anchor`, linear), and
// node pairs joined by per-component springs with force k d + k3 d^3 on the separation change
// d = (x_b - x_a) - (X_b - X_a). Energy sum anchor/2 |x - X|^2 + k/2 d^2 + k3/4 d^4.
// Optionally the force becomes NaN when a node moves further than nanBeyond from rest.
class TestSprings : public ForceModel {
 public:
  TestSprings(Eigen::Matrix3Xd rest, double anchor, std::vector<std::array<int, 2>> pairs,
              double k, double k3)
      : rest_(std::move(rest)), anchor_(anchor), pairs_(std::move(pairs)), k_(k), k3_(k3) {}

  const char* name() const override { return "test_springs"; }
  double nanBeyond = std::numeric_limits<double>::infinity();

  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& /*v*/,
                  Eigen::VectorXd& f) const override {
    for (int a = 0; a < rest_.cols(); ++a) {
      const Eigen::Vector3d u = x.segment<3>(3 * a) - rest_.col(a);
      if (u.norm() > nanBeyond) f[3 * a] = std::numeric_limits<double>::quiet_NaN();
      f.segment<3>(3 * a) -= anchor_ * u;
    }
    for (const auto& [a, b] : pairs_) {
      const Eigen::Vector3d d = separationChange(x, a, b);
      const Eigen::Vector3d s = k_ * d + k3_ * d.cwiseProduct(d).cwiseProduct(d);
      f.segment<3>(3 * a) += s;
      f.segment<3>(3 * b) -= s;
    }
    return energy(x);
  }

  double energy(const Eigen::VectorXd& x) const override {
    double e = 0.0;
    for (int a = 0; a < rest_.cols(); ++a)
      e += 0.5 * anchor_ * (x.segment<3>(3 * a) - rest_.col(a)).squaredNorm();
    for (const auto& [a, b] : pairs_) {
      const Eigen::Vector3d d = separationChange(x, a, b);
      e += 0.5 * k_ * d.squaredNorm() + 0.25 * k3_ * d.array().pow(4).sum();
    }
    return e;
  }

  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override {
    for (int a = 0; a < rest_.cols(); ++a)
      pattern.addNodeBlock(K, a, a, -scale * anchor_ * Eigen::Matrix3d::Identity());
    for (const auto& [a, b] : pairs_) {
      const Eigen::Vector3d d = separationChange(x, a, b);
      const Eigen::Matrix3d S =
          scale * (k_ * Eigen::Vector3d::Ones() + 3.0 * k3_ * d.cwiseProduct(d)).asDiagonal();
      pattern.addNodeBlock(K, a, a, -S);
      pattern.addNodeBlock(K, b, b, -S);
      pattern.addNodeBlock(K, a, b, S);
      pattern.addNodeBlock(K, b, a, S);
    }
  }

 private:
  Eigen::Vector3d separationChange(const Eigen::VectorXd& x, int a, int b) const {
    return x.segment<3>(3 * b) - x.segment<3>(3 * a) - (rest_.col(b) - rest_.col(a));
  }
  Eigen::Matrix3Xd rest_;
  double anchor_;
  std::vector<std::array<int, 2>> pairs_;
  double k_, k3_;
};

// Nodes along x (spacing 0.1 m), each of the given mass, chained by springs when k or k3 != 0.
std::unique_ptr<System> springSystem(int nodes, double mass, double anchor, double k,
                                     double k3) {
  Mesh mesh;
  mesh.rest = Eigen::Matrix3Xd::Zero(3, nodes);
  for (int a = 0; a < nodes; ++a) mesh.rest(0, a) = 0.1 * a;
  mesh.fillDefaults();
  auto system = std::make_unique<System>(mesh, std::vector<Material>{});
  std::vector<std::array<int, 2>> pairs;
  if (k != 0.0 || k3 != 0.0)
    for (int a = 0; a + 1 < nodes; ++a) pairs.push_back({a, a + 1});
  system->pattern = SparsePattern(nodes, {}, pairs);
  system->mass = Eigen::VectorXd::Constant(3 * nodes, mass);
  system->models.push_back(std::make_unique<TestSprings>(mesh.rest, anchor, pairs, k, k3));
  return system;
}

// ---- Constants ---------------------------------------------------------------------------

TEST(RadauTableau, MatchesThePrintedTableauAndHasOrderFive) {
  const RadauTableau& r = RadauTableau::get();
  const double s6 = std::sqrt(6.0);
  // Jeffrey, "A non-linear anisotropic Finite Element Method for surgical simulation", App. D.
  Eigen::Matrix3d printed;
  printed << (88 - 7 * s6) / 360, (296 - 169 * s6) / 1800, (-2 + 3 * s6) / 225,
      (296 + 169 * s6) / 1800, (88 + 7 * s6) / 360, (-2 - 3 * s6) / 225,
      (16 - s6) / 36, (16 + s6) / 36, 1.0 / 9;
  EXPECT_LT((r.A - printed).cwiseAbs().maxCoeff(), 1e-14);
  // Radau quadrature is exact for polynomials of degree 2s - 2 = 4.
  for (int k = 1; k <= 5; ++k) {
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) sum += r.b[i] * std::pow(r.c[i], k - 1);
    EXPECT_NEAR(sum, 1.0 / k, 1e-14) << "k = " << k;
  }
  double sum6 = 0.0;
  for (int i = 0; i < 3; ++i) sum6 += r.b[i] * std::pow(r.c[i], 5);
  EXPECT_GT(std::abs(sum6 - 1.0 / 6), 1e-4);  // and not beyond
  // d = b A^-1 = (0, 0, 1) (D.6): y1 = y0 + z3.
  const Eigen::RowVector3d d = r.b.transpose() * r.Ainv;
  EXPECT_LT((d - Eigen::RowVector3d(0, 0, 1)).norm(), 1e-13);
}

TEST(RadauTableau, TransformationBlockDiagonalisesTheInverseCoefficientMatrix) {
  const RadauTableau& r = RadauTableau::get();
  Eigen::Matrix3d expected;
  expected << r.gamma, 0, 0, 0, r.alpha, -r.beta, 0, r.beta, r.alpha;
  EXPECT_LT((r.Tinv * r.Ainv * r.T - expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT(r.beta, 0.0);
  // The eigenvalues of A^-1 are the poles of the stability function R(z) = P(z)/Q(z) with
  // Q(z) = 1 - 3z/5 + 3z^2/20 - z^3/60, i.e. the roots of z^3 - 9z^2 + 36z - 60.
  auto poly = [](std::complex<double> z) { return z * z * z - 9.0 * z * z + 36.0 * z - 60.0; };
  EXPECT_LT(std::abs(poly(r.gamma)), 1e-11);
  EXPECT_LT(std::abs(poly({r.alpha, r.beta})), 1e-11);
  EXPECT_NEAR(r.gamma, 3.6378342527444957, 1e-12);
}

TEST(RadauTableau, ErrorWeightsAreThePrintedOnesAndGiveAnOrderThreeEmbeddedMethod) {
  const RadauTableau& r = RadauTableau::get();
  const double s6 = std::sqrt(6.0);
  const Eigen::Vector3d printed = Eigen::Vector3d(-13 - 7 * s6, -13 + 7 * s6, -1) / (3 * r.gamma);
  EXPECT_LT((r.errorWeights - printed).norm(), 1e-12);
  // y_hat - y = h (gamma0 F(y0) + sum_i delta_i F_i) with delta = A^T e. For y' = t^(k-1) the
  // difference vanishes for k = 1..3 (order 3) and not for k = 4.
  const Eigen::Vector3d delta = r.A.transpose() * r.errorWeights;
  for (int k = 1; k <= 4; ++k) {
    double diff = (k == 1 ? 1.0 / r.gamma : 0.0);
    for (int i = 0; i < 3; ++i) diff += delta[i] * std::pow(r.c[i], k - 1);
    if (k <= 3) EXPECT_NEAR(diff, 0.0, 1e-13) << "k = " << k;
    else EXPECT_GT(std::abs(diff), 1e-3);
  }
}

TEST(RadauTableau, ExtrapolationReproducesCubics) {
  const RadauTableau& r = RadauTableau::get();
  auto p = [](double s) { return 0.7 * s - 1.3 * s * s + 0.4 * s * s * s; };  // p(0) = 0
  for (double ratio : {0.5, 1.0, 1.7}) {
    const Eigen::Matrix3d P = r.extrapolation(ratio);
    Eigen::Vector3d z(p(r.c[0]), p(r.c[1]), p(r.c[2]));
    const Eigen::Vector3d start = P * z;
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(start[i], p(1.0 + ratio * r.c[i]) - p(1.0), 1e-13) << ratio;
  }
}

// ---- The test model ----------------------------------------------------------------------

TEST(RadauTestModel, ForceIsMinusEnergyGradientAndStiffnessIsForceDerivative) {
  auto system = springSystem(3, 1.0, 2.0, 5.0, 300.0);
  Eigen::VectorXd x = system->state.x + 0.05 * Eigen::VectorXd::Random(9);
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(9);
  Eigen::VectorXd f;
  system->computeForce(x, v, f);
  SparseMatrix K;
  system->assembleStiffness(x, K);
  const Eigen::MatrixXd dense = K;
  const double eps = 1e-6;
  for (int j = 0; j < 9; ++j) {
    Eigen::VectorXd xp = x, xm = x, fp, fm;
    xp[j] += eps;
    xm[j] -= eps;
    const double dE = (system->potentialEnergy(xp) - system->potentialEnergy(xm)) / (2 * eps);
    EXPECT_NEAR(f[j], -dE, 1e-7);
    system->computeForce(xp, v, fp);
    system->computeForce(xm, v, fm);
    EXPECT_LT(((fp - fm) / (2 * eps) - dense.col(j)).norm(), 1e-6);
  }
}

// ---- Accuracy ----------------------------------------------------------------------------

// One node on an anchor spring, omega = 1 rad/s, released from a displacement at rest.
double oscillatorError(RadauOptions options, double time, StepReport* out = nullptr) {
  auto system = springSystem(1, 2.0, 2.0, 0.0, 0.0);
  const Eigen::Vector3d d0(0.3, -0.2, 0.1);
  system->state.x += d0;
  RadauIIA radau(options);
  const StepReport report = radau.advance(*system, time);
  EXPECT_TRUE(report.ok) << report.failure;
  if (out) *out = report;
  const Eigen::Vector3d xe = d0 * std::cos(time), ve = -d0 * std::sin(time);
  return std::max((system->state.x - xe).cwiseAbs().maxCoeff(),
                  (system->state.v - ve).cwiseAbs().maxCoeff());
}

TEST(RadauIIA, FixedStepGlobalErrorIsOfOrderFive) {
  RadauOptions options;
  options.adaptive = false;
  options.absTol = options.relTol = 1e-14;
  std::vector<double> steps, errors;
  for (int count : {4, 8, 16, 32, 64}) {
    options.initialStep = 4.0 / count;
    steps.push_back(options.initialStep);
    errors.push_back(oscillatorError(options, 4.0));
    std::cout << "  fixed h = " << steps.back() << "  error = " << errors.back() << "\n";
  }
  const double order = oscillators::logSlope(steps, errors);
  std::cout << "  fitted order " << order << "\n";
  EXPECT_NEAR(order, 5.0, 0.5);
}

// The stability guard's retries: fixed steps are `divisor` times shorter, and the error falls
// as for steps set that short.
TEST(RadauIIA, StepDivisorShortensTheFixedSteps) {
  RadauOptions options;
  options.adaptive = false;
  options.absTol = options.relTol = 1e-14;
  options.initialStep = 0.5;
  const auto run = [&](int divisor, StepReport& report) {
    auto system = springSystem(1, 2.0, 2.0, 0.0, 0.0);
    system->state.x += Eigen::Vector3d(0.3, -0.2, 0.1);
    RadauIIA radau(options);
    radau.setStepDivisor(divisor);
    report = radau.advance(*system, 2.0);
    return system->state.x;
  };
  StepReport plain, divided, restored;
  const Eigen::VectorXd x1 = run(1, plain), x4 = run(4, divided), x1again = run(1, restored);
  EXPECT_EQ(plain.substeps, 4);
  EXPECT_EQ(divided.substeps, 16);
  EXPECT_EQ(restored.substeps, 4);
  EXPECT_EQ(x1, x1again);
  options.initialStep = 0.125;
  StepReport set;
  EXPECT_EQ(run(1, set), x4);  // the same steps as when set that short
}

TEST(RadauIIA, AdaptiveErrorTracksTheTolerance) {
  std::vector<double> tolerances, errors;
  for (double tol : {1e-4, 1e-6, 1e-8, 1e-10}) {
    RadauOptions options;
    options.absTol = options.relTol = tol;
    StepReport report;
    tolerances.push_back(tol);
    errors.push_back(oscillatorError(options, 10.0, &report));
    std::cout << "  tol " << tol << "  error " << errors.back() << "  steps " << report.substeps
              << "  rejected " << report.rejected << "  newton " << report.newtonIterations
              << "\n";
    EXPECT_LT(errors.back(), 100 * tol);
    EXPECT_GT(errors.back(), 1e-3 * tol);  // not wastefully tight either
  }
  const double rate = oscillators::logSlope(tolerances, errors);
  std::cout << "  error ~ tol^" << rate << "\n";
  EXPECT_NEAR(rate, 1.0, 0.3);
}

TEST(RadauIIA, SplittingIntoFramesKeepsTheAccuracy) {
  // Ten frames carry the step size and the stage polynomial across frame boundaries.
  auto system = springSystem(1, 2.0, 2.0, 0.0, 0.0);
  const Eigen::Vector3d d0(0.3, -0.2, 0.1);
  system->state.x += d0;
  RadauOptions options;
  options.absTol = options.relTol = 1e-8;
  RadauIIA radau(options);
  int steps = 0;
  for (int frame = 0; frame < 10; ++frame) {
    const StepReport r = radau.advance(*system, 1.0);
    ASSERT_TRUE(r.ok);
    steps += r.substeps;
  }
  std::cout << "  10 frames of 1 s: " << steps << " steps\n";
  EXPECT_NEAR(system->state.t, 10.0, 1e-12);
  EXPECT_LT((system->state.x - d0 * std::cos(10.0)).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_LT(steps, 120);  // one frame of 10 s needs ~75 at this tolerance
}

// ---- Jacobian modes ----------------------------------------------------------------------

struct ModeRun {
  Eigen::VectorXd x, v;
  StepReport total;
};

ModeRun runChain(RadauJacobian mode, double tol) {
  // Five nodes of 10 g, stiff cubic springs between neighbours, node 0 fixed, overdamped like
  // tissue: the motion is slow while the chain's frequencies reach ~400 rad/s.
  auto system = springSystem(5, 0.01, 1.0, 400.0, 4e5);
  system->mesh.nodeTags[0] = kFixedAll;
  system->damping.setConstant(5.0);
  system->updateConstraints();
  for (int a = 1; a < 5; ++a)
    system->state.x.segment<3>(3 * a) += Eigen::Vector3d(0.04 * a, -0.03, 0.02 * (a % 2));
  RadauOptions options;
  options.jacobian = mode;
  options.absTol = options.relTol = tol;
  options.initialStep = 0.01;
  RadauIIA radau(options);
  ModeRun run;
  for (int frame = 0; frame < 10; ++frame) {
    const StepReport r = radau.advance(*system, 0.05);
    EXPECT_TRUE(r.ok) << r.failure;
    run.total.substeps += r.substeps;
    run.total.rejected += r.rejected;
    run.total.newtonIterations += r.newtonIterations;
    run.total.jacobians += r.jacobians;
    run.total.linearIterations += r.linearIterations;
  }
  run.x = system->state.x;
  run.v = system->state.v;
  return run;
}

TEST(RadauIIA, JacobianModesAgreeAndDifferInCost) {
  const double tol = 1e-8;
  const ModeRun analytical = runChain(RadauJacobian::kAnalytical, tol);
  const ModeRun numerical = runChain(RadauJacobian::kNumerical, tol);
  const ModeRun simplified = runChain(RadauJacobian::kSimplified, tol);
  const ModeRun reference = runChain(RadauJacobian::kAnalytical, 1e-12);
  for (const auto* run : {&analytical, &numerical, &simplified}) {
    std::cout << "  steps " << run->total.substeps << " rejected " << run->total.rejected
              << " newton " << run->total.newtonIterations << " jacobians "
              << run->total.jacobians << " solves " << run->total.linearIterations
              << "  |x - ref| " << (run->x - reference.x).cwiseAbs().maxCoeff() << "\n";
    EXPECT_LT((run->x - reference.x).cwiseAbs().maxCoeff(), 1e-5);
    EXPECT_LT((run->v - reference.v).cwiseAbs().maxCoeff(), 1e-4);
  }
  EXPECT_EQ(simplified.total.jacobians, 0);
  EXPECT_GT(analytical.total.jacobians, 0);
  EXPECT_GT(numerical.total.jacobians, 0);
  EXPECT_GT(simplified.total.newtonIterations, 2 * analytical.total.newtonIterations);
  // The finite-difference Jacobian is the analytic one up to O(sqrt(eps)): same work.
  EXPECT_NEAR(numerical.total.newtonIterations, analytical.total.newtonIterations,
              0.2 * analytical.total.newtonIterations);
}

// ---- Stiffness ---------------------------------------------------------------------------

TEST(RadauIIA, VeryStiffSpringDecaysAtLargeSteps) {
  const double h = 0.01, omega = 1e4 / h;  // h * omega = 1e4
  auto system = springSystem(1, 1.0, omega * omega, 0.0, 0.0);
  system->state.x[0] += 1e-3;
  RadauOptions options;
  options.adaptive = false;
  options.initialStep = h;
  RadauIIA radau(options);
  auto energy = [&]() {
    return system->potentialEnergy(system->state.x) + system->kineticEnergy(system->state.v);
  };
  double previous = energy();
  const double initial = previous;
  for (int step = 0; step < 4; ++step) {
    const StepReport r = radau.advance(*system, h);
    ASSERT_TRUE(r.ok) << r.failure;
    EXPECT_TRUE(system->state.x.allFinite() && system->state.v.allFinite());
    const double e = energy();
    std::cout << "  step " << step + 1 << "  energy / initial " << e / initial << "\n";
    EXPECT_LT(e, 1e-5 * previous + 1e-300);  // |R(i 1e4)|^2 ~ 1e-7 per step
    previous = e;
  }
}

TEST(RadauIIA, AdaptiveStepsAreNotLimitedByAStiffComponent) {
  // Two 1 kg nodes on soft anchors (1 N/m) joined by a 1e12 N/m spring: the in-phase mode has
  // omega = 1 rad/s, the relative mode omega = 1.4e6 rad/s. Released in the soft mode.
  auto system = springSystem(2, 1.0, 1.0, 1e12, 0.0);
  system->state.x[0] += 0.1;
  system->state.x[3] += 0.1;
  RadauOptions options;
  options.absTol = options.relTol = 1e-6;
  RadauIIA radau(options);
  const StepReport r = radau.advance(*system, 2.0);
  ASSERT_TRUE(r.ok) << r.failure;
  std::cout << "  steps " << r.substeps << " rejected " << r.rejected << " last h " << r.lastStep
            << "\n";
  EXPECT_LT(r.substeps + r.rejected, 200);  // an explicit method needs > 1.4e6 steps
  EXPECT_NEAR(system->state.x[0], 0.1 * std::cos(2.0), 1e-5);
  EXPECT_NEAR(system->state.x[3] - 0.1, 0.1 * std::cos(2.0), 1e-5);
}

// ---- Constraints and failure -------------------------------------------------------------

TEST(RadauIIA, ConstrainedNodesFollowTheirPathAndDriveTheFreeNode) {
  // Node 0 fixed, node 2 pulled along x at speed u, node 1 between two springs k:
  // m x'' = -2 k x + k u t, x(0) = x'(0) = 0  ->  x = u t / 2 - u / (2 W) sin(W t), W^2 = 2k/m.
  const double m = 0.5, k = 8.0, u = 0.2, W = std::sqrt(2 * k / m);
  for (RadauJacobian mode : {RadauJacobian::kAnalytical, RadauJacobian::kSimplified}) {
    auto system = springSystem(3, m, 0.0, k, 0.0);
    system->mesh.nodeTags[0] = kFixedAll;
    system->controlled.push_back(
        {{2}, {{0.0, 10.0}, {Eigen::Vector3d::Zero(), Eigen::Vector3d(10 * u, 0, 0)}}});
    system->updateConstraints();
    RadauOptions options;
    options.jacobian = mode;
    options.absTol = options.relTol = 1e-9;
    RadauIIA radau(options);
    for (int frame = 1; frame <= 20; ++frame) {
      ASSERT_TRUE(radau.advance(*system, 0.05).ok);
      const double t = 0.05 * frame;
      const Eigen::VectorXd& x = system->state.x;
      EXPECT_EQ(x.segment<3>(0), Eigen::Vector3d::Zero());
      EXPECT_NEAR(x[6], 0.2 + u * t, 1e-15);
      EXPECT_NEAR(system->state.v[6], u, 1e-15);
      EXPECT_NEAR(x[3] - 0.1, u * t / 2 - u / (2 * W) * std::sin(W * t), 1e-7);
      EXPECT_NEAR(x[4], 0.0, 1e-15);
    }
  }
}

TEST(RadauIIA, NonFiniteForceFailsAndRestoresTheFrameStart) {
  // A constant pull moves the node past the point where the force turns NaN mid-frame.
  auto system = springSystem(1, 1.0, 0.0, 0.0, 0.0);
  auto* springs = static_cast<TestSprings*>(system->models[0].get());
  springs->nanBeyond = 0.1;
  system->externalForce[0] = 1.0;
  system->state.t = 3.0;
  const State start = system->state;
  RadauOptions options;
  options.minStep = 1e-10;
  options.maxStepsPerFrame = 2000;
  RadauIIA radau(options);
  const StepReport r = radau.advance(*system, 1.0);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.failure.empty());
  EXPECT_EQ(system->state.x, start.x);
  EXPECT_EQ(system->state.v, start.v);
  EXPECT_EQ(system->state.t, start.t);
  // Already non-finite at the start: fails at once, state untouched.
  system->state.x[1] = 0.5;
  const State bad = system->state;
  const StepReport r2 = radau.advance(*system, 0.1);
  EXPECT_FALSE(r2.ok);
  EXPECT_EQ(system->state.x, bad.x);
  // A frame that stays inside the finite region succeeds.
  system->state = start;
  EXPECT_TRUE(radau.advance(*system, 0.3).ok);
  EXPECT_NEAR(system->state.x[0], 0.045, 1e-9);
}

TEST(RadauIIA, RefusesMasslessFreeDofsAndAnalyticalModeWithoutStiffness) {
  auto system = springSystem(2, 1.0, 1.0, 0.0, 0.0);
  system->mass[4] = 0.0;
  RadauIIA radau;
  EXPECT_FALSE(radau.advance(*system, 0.01).ok);
  system->mesh.nodeTags[1] = kFixedY;  // the massless DOF is now prescribed
  system->updateConstraints();
  EXPECT_TRUE(radau.advance(*system, 0.01).ok);

  class NoStiffness : public TestSprings {
   public:
    using TestSprings::TestSprings;
    bool hasStiffness() const override { return false; }
  };
  system->models.clear();
  system->models.push_back(std::make_unique<NoStiffness>(system->mesh.rest, 1.0,
                                                         std::vector<std::array<int, 2>>{}, 0, 0));
  EXPECT_FALSE(radau.advance(*system, 0.01).ok);
  RadauOptions numerical;
  numerical.jacobian = RadauJacobian::kNumerical;
  EXPECT_TRUE(RadauIIA(numerical).advance(*system, 0.01).ok);
}

}  // namespace
}  // namespace tt
