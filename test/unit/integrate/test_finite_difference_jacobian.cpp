// Finite-difference Jacobians of the total force (solve/finite_difference_jacobian.h):
// against the assembled analytic stiffness and velocity Jacobian on a small neo-Hookean mesh
// with axis friction and per-DOF damping, coloured and not; the colouring is valid and far
// smaller than one group per DOF; backward Euler with them takes the analytic step, and runs
// models that have no analytic stiffness, solving their implicit equations.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "../model_test_util.h"
#include "implicit_test_util.h"
#include "oscillators.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/material/neo_hookean.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/adamss/axis_friction.h"
#include "tissue_trainer/core/model/adamss/torsion_springs.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/solve/finite_difference_jacobian.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace {

using testutil::boxMesh;
using testutil::perturbed;
using testutil::testMaterials;

// A jittered 2 x 2 x 2 box of neo-Hookean tets with axis friction and per-DOF damping, at a
// deformed state.
std::unique_ptr<System> frictionBox(std::mt19937& rng) {
  auto s = std::make_unique<System>(boxMesh(2, 2, 2, 0.01, rng, 0.1), testMaterials());
  std::vector<NeoHookeanLaw::Constants> constants;
  for (const Material& m : s->materials) constants.push_back(NeoHookeanLaw::constants(m));
  s->models.push_back(std::make_unique<HyperelasticModel<NeoHookeanLaw>>(s->mesh, constants,
                                                                        LawOptions{}));
  s->models.push_back(std::make_unique<adamss::AxisFrictionModel>(
      s->mesh, 3.0, adamss::AxisFrictionForm::kBourguignon));
  s->damping.setConstant(0.05);
  s->state.x = perturbed(s->mesh, 8e-4, rng);
  return s;
}

double maxAbs(const SparseMatrix& A) {
  return Eigen::Map<const Eigen::VectorXd>(A.valuePtr(), A.nonZeros()).lpNorm<Eigen::Infinity>();
}

// Largest entry difference relative to the largest entry of `reference` (same pattern).
double relativeDifference(const SparseMatrix& a, const SparseMatrix& reference) {
  EXPECT_EQ(a.nonZeros(), reference.nonZeros());
  const SparseMatrix difference = a - reference;
  return maxAbs(difference) / maxAbs(reference);
}

// The perturbation is 1.5e-8 of the 2 cm box: the truncation error is about that fraction
// of the stiffness, the rounding error about 1e-16 |f| / (1.5e-8 * 2 cm) of it.
constexpr double kDifferenceTolerance = 1e-5;

TEST(FiniteDifferenceJacobian, MatchesTheAnalyticStiffnessAndVelocityJacobian) {
  std::mt19937 rng(7);
  auto s = frictionBox(rng);
  // At rest velocities the friction has no position derivative (it is linear in v), so
  // df/dx is the analytic stiffness, which leaves that derivative out.
  const Eigen::VectorXd x = s->state.x, rest = Eigen::VectorXd::Zero(x.size());
  Eigen::VectorXd v = perturbed(s->mesh, 0.05, rng) - testutil::restVector(s->mesh);
  SparseMatrix K, C;
  s->assembleStiffness(x, K);
  s->assembleVelocityJacobian(x, v, C);
  for (int dof = 0; dof < s->numDofs(); ++dof) C.coeffRef(dof, dof) -= s->damping[dof];
  ASSERT_GT(maxAbs(C), 0.0);
  for (bool coloring : {false, true}) {
    FiniteDifferenceSettings settings;
    settings.coloring = coloring;
    FiniteDifferenceJacobian fd(*s, settings);
    Eigen::VectorXd f;
    s->computeForce(x, rest, f);
    SparseMatrix Kfd, Cfd;
    fd.positions(*s, x, rest, f, 1.0, Kfd);
    EXPECT_LT(relativeDifference(Kfd, K), kDifferenceTolerance) << "coloring " << coloring;
    s->computeForce(x, v, f);
    fd.velocities(*s, x, v, f, 1.0, Cfd);
    EXPECT_LT(relativeDifference(Cfd, C), kDifferenceTolerance) << "coloring " << coloring;
    // The scale multiplies the result.
    SparseMatrix scaled;
    s->computeForce(x, rest, f);
    fd.positions(*s, x, rest, f, -0.25, scaled);
    EXPECT_LT(relativeDifference(scaled, SparseMatrix(-0.25 * Kfd)), 1e-15);
    EXPECT_EQ(fd.forceEvaluations(), 3 * fd.groups());
    if (!coloring) EXPECT_EQ(fd.groups(), s->numDofs());
  }
}

// A perturbation ten times larger makes the error about ten times larger: what is measured is
// the truncation error of the forward difference, not an accident.
TEST(FiniteDifferenceJacobian, ErrorFollowsThePerturbation) {
  std::mt19937 rng(11);
  auto s = frictionBox(rng);
  const Eigen::VectorXd x = s->state.x, v = Eigen::VectorXd::Zero(x.size());
  SparseMatrix K;
  s->assembleStiffness(x, K);
  Eigen::VectorXd f;
  s->computeForce(x, v, f);
  std::vector<double> errors;
  for (double epsilon : {1e-5, 1e-4, 1e-3}) {
    FiniteDifferenceSettings settings;
    settings.epsilon = epsilon;
    FiniteDifferenceJacobian fd(*s, settings);
    SparseMatrix Kfd;
    fd.positions(*s, x, v, f, 1.0, Kfd);
    errors.push_back(relativeDifference(Kfd, K));
  }
  EXPECT_GT(errors[1] / errors[0], 5.0);
  EXPECT_LT(errors[1] / errors[0], 20.0);
  EXPECT_GT(errors[2] / errors[1], 5.0);
  EXPECT_LT(errors[2] / errors[1], 20.0);
}

// Two nodes of one colour share no row of the pattern: neither is the other's neighbour and
// no node neighbours both.
TEST(FiniteDifferenceJacobian, ColouringIsValidAndFarSmallerThanTheDofCount) {
  const Mesh mesh = boxGrid(10, 10, 10, Eigen::Vector3d(0.05, 0.05, 0.05), TetSplit::kSixMirrored);
  const System s(mesh, {Material::isotropic(5e3, 0.4, 1000.0)});
  const std::vector<int> colour = distanceTwoColouring(s.pattern);
  const SparseMatrix pattern = s.pattern.zeroMatrix();
  for (int row = 0; row < pattern.rows(); row += 3) {
    std::vector<int> seen;
    for (SparseMatrix::InnerIterator it(pattern, row); it; ++it)
      if (it.col() % 3 == 0) seen.push_back(colour[it.col() / 3]);
    std::sort(seen.begin(), seen.end());
    EXPECT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end()) << "row " << row;
  }
  const FiniteDifferenceJacobian fd(s, {});
  EXPECT_EQ(fd.groups(), 3 * fd.colours());
  EXPECT_LE(fd.colours(), 40) << "greedy distance-2 colouring of a structured grid";
  EXPECT_LT(10 * fd.groups(), s.numDofs()) << fd.groups() << " groups for " << s.numDofs()
                                           << " DOFs";
}

// A model that couples two far nodes (a spring) widens the pattern without changing the DOF
// count: the Jacobian built before no longer matches, so backward Euler builds a new one.
TEST(FiniteDifferenceJacobian, NoLongerMatchesWhenCouplingsWidenThePattern) {
  const Mesh mesh = boxGrid(3, 3, 3, Eigen::Vector3d(0.02, 0.02, 0.02), TetSplit::kSix);
  System s(mesh, {Material::isotropic(5e3, 0.4, 1000.0)});
  const FiniteDifferenceJacobian fd(s, {});
  EXPECT_TRUE(fd.matches(s));
  s.pattern = meshPattern(s.mesh, {{0, s.numNodes() - 1}});
  EXPECT_FALSE(fd.matches(s));
}

// Eq. 2.149 as printed, (F_d - F^_d) / du, is minus the force Jacobian. On unit-mass
// oscillators with k = 100 and h = 0.05, 400 linearised steps (Eqs. 2.146-2.148, multiplied by
// M: (M - h^2 J) dv = h (f + h J v)) with the printed sign amplify the motion beyond 1e10,
// with the corrected one they damp it below 1e-10 (backward Euler damps).
TEST(FiniteDifferenceJacobian, Eq2149AsPrintedBlowsUpAndCorrectedDamps) {
  oscillators::Oscillators o;
  o.k = Eigen::VectorXd::Constant(12, 100.0);
  o.u0 = Eigen::VectorXd::Constant(12, 0.1);
  o.v0 = Eigen::VectorXd::Zero(12);
  const double h = 0.05;
  for (double sign : {-1.0, 1.0}) {  // -1: as printed
    System s = o.build();
    FiniteDifferenceJacobian fd(s, {});
    SparseMatrix J;
    Eigen::VectorXd f;
    for (int step = 0; step < 400; ++step) {
      s.computeForce(s.state.x, s.state.v, f);
      fd.positions(s, s.state.x, s.state.v, f, sign, J);
      const Eigen::MatrixXd A = Eigen::MatrixXd(s.mass.asDiagonal()) - h * h * Eigen::MatrixXd(J);
      const Eigen::VectorXd dv = A.partialPivLu().solve(h * (f + h * (J * s.state.v)));
      s.state.v += dv;
      s.state.x += h * s.state.v;
    }
    const double amplitude = (s.state.x - oscillators::restVector(s)).lpNorm<Eigen::Infinity>();
    if (sign < 0)
      EXPECT_GT(amplitude, 1e10);
    else
      EXPECT_LT(amplitude, 1e-10);
  }
}

BackwardEulerParams tightParams(BackwardEulerParams::Jacobian jacobian) {
  BackwardEulerParams p;
  p.linearTolerance = 1e-12;
  p.linearMaxIterations = 5000;
  p.linearSolver = BackwardEulerParams::LinearSolver::kGmres;
  p.jacobian = jacobian;
  return p;
}

TEST(FiniteDifferenceJacobian, BackwardEulerStepAgreesWithTheAnalyticOne) {
  using Jacobian = BackwardEulerParams::Jacobian;
  auto analytic = testutil::beam(), coloured = testutil::beam(), plain = testutil::beam();
  const Eigen::VectorXd start = analytic->state.x;
  BackwardEulerIntegrator a(tightParams(Jacobian::kAnalytic));
  BackwardEulerParams p = tightParams(Jacobian::kFiniteDifference);
  BackwardEulerIntegrator c(p);
  p.finiteDifference.coloring = false;
  BackwardEulerIntegrator d(p);
  EXPECT_FALSE(c.needsStiffness());
  for (int frame = 0; frame < 3; ++frame) {
    ASSERT_TRUE(a.advance(*analytic, 0.02).ok);
    ASSERT_TRUE(c.advance(*coloured, 0.02).ok);
    ASSERT_TRUE(d.advance(*plain, 0.02).ok);
  }
  // The difference is the forward difference's truncation error, proportional to the
  // perturbation: 2e-7 of the travel per 1e-8 of epsilon (1.5e-8 by default) on this beam.
  const double travel = (analytic->state.x - start).lpNorm<Eigen::Infinity>();
  ASSERT_GT(travel, 1e-3);
  EXPECT_LT((coloured->state.x - analytic->state.x).lpNorm<Eigen::Infinity>(), 1e-5 * travel);
  EXPECT_LT((plain->state.x - analytic->state.x).lpNorm<Eigen::Infinity>(), 1e-5 * travel);
  EXPECT_LT(2 * c.diagnostics().jacobianForceEvaluations, d.diagnostics().jacobianForceEvaluations);
  EXPECT_EQ(a.diagnostics().jacobianForceEvaluations, 0);
}

// Torsion springs in their printed form have no analytic stiffness: with finite differences
// backward Euler runs them, and full Newton on its Jacobians solves the implicit equations
// M dv = h f(x + h (v + dv), v + dv) of every free DOF.
TEST(FiniteDifferenceJacobian, RunsAModelWithoutStiffnessAndSolvesItsImplicitEquations) {
  std::mt19937 rng(3);
  auto s = std::make_unique<System>(boxMesh(2, 2, 1, 0.01, rng, 0.1), testMaterials());
  adamss::TorsionSpringParameters torsion;
  torsion.k = {{{3.4e-2, 0.0, 0.974}, {0.974, 1e-2, 3.4e-2}, {0.459, 0.0, 2.3e-2}}};  // J
  torsion.gradient = false;
  s->models.push_back(std::make_unique<adamss::TorsionSpringModel>(s->mesh, torsion));
  ASSERT_FALSE(s->hasStiffness());
  s->damping = 0.5 * s->mass;
  s->state.x = perturbed(s->mesh, 3e-4, rng);
  BackwardEulerParams p = tightParams(BackwardEulerParams::Jacobian::kFiniteDifference);
  p.newtonIterations = 20;
  p.newtonTolerance = 1e-9;
  p.requireConvergence = true;
  BackwardEulerIntegrator be(p);
  const State before = s->state;
  const double h = 1e-4;
  const StepReport r = be.advance(*s, h);
  ASSERT_TRUE(r.ok) << r.failure;
  const Eigen::VectorXd dv = s->state.v - before.v;
  EXPECT_GT(dv.norm(), 0.0);
  Eigen::VectorXd f;
  s->computeForce(s->state.x, s->state.v, f);
  const Eigen::VectorXd residual = s->mass.cwiseProduct(dv) - h * f;
  EXPECT_LT(residual.norm(), 1e-8 * (h * f).norm());
  EXPECT_EQ(be.diagnostics().unconvergedNewton, 0);
}

}  // namespace
}  // namespace tt
