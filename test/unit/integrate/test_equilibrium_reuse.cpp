// What makes the warm-started quasistatic update cheap (solve/equilibrium.h): the Cholesky
// factor kept across Newton iterations and solves gives the equilibria of a new factor every
// iteration, with fewer factorisations; the energy the line search reads from the force pass
// is the models' energy; muscle_groups' one-pass total follows activation changes made by
// setActivation and by its activation curves.
#include <gtest/gtest.h>

#include <random>

#include "../model_test_util.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/collision.h"
#include "tissue_trainer/core/model/gravity.h"
#include "tissue_trainer/core/model/muscle_groups.h"
#include "tissue_trainer/core/solve/equilibrium.h"

namespace tt {
namespace {

// A soft muscle beam along x clamped at x = 0 and sagging under gravity, two muscles (upper and
// lower half) with fibres along x, inversion handling on, a plane above that the contracting
// upper muscle lifts the tip against.
std::unique_ptr<System> muscleBeam() {
  Mesh mesh = cantileverBeam(0.06, 0.012, 10, 3);
  auto s = std::make_unique<System>(mesh, std::vector<Material>{Material::isotropic(6e3, 0.45, 1050.0)});
  TeranMuscleLaw::Constants k;
  k.A = 2e3, k.B = 0.5e3, k.K = 50e3, k.sigmaMax = 30e3;
  std::vector<MuscleGroup> groups(2);
  groups[0].name = "upper", groups[1].name = "lower";
  for (int e = 0; e < s->mesh.numTets(); ++e) {
    double z = 0.0;
    for (int n : s->mesh.tets[e]) z += 0.25 * s->mesh.rest(2, n);
    groups[z > 0.0 ? 0 : 1].elements.push_back(e);
  }
  LawOptions options;
  options.inversionThreshold = 0.2;
  s->models.push_back(std::make_unique<MuscleGroupsModel>(
      s->mesh, std::vector<TeranMuscleLaw::Constants>{k}, groups, options));
  std::vector<int> nodes(s->numNodes());
  for (int n = 0; n < s->numNodes(); ++n) nodes[n] = n;
  s->models.push_back(std::make_unique<CollisionModel>(
      s->numNodes(), nodes, 200.0,
      std::vector<CollisionBody>{CollisionBody::plane(Eigen::Vector3d(0, 0, 0.012),
                                                      Eigen::Vector3d(0, 0, -1))},
      std::vector<ClosedSurface>{}, false));
  s->models.push_back(std::make_unique<GravityModel>(s->mass, Eigen::Vector3d(0, 0, -9.81)));
  s->updateConstraints();
  return s;
}

TEST(Equilibrium, KeptCholeskyFactorGivesTheEquilibriaOfNewFactors) {
  auto kept = muscleBeam();
  auto fresh = muscleBeam();
  EquilibriumParams p;
  p.preconditioner = EquilibriumParams::Preconditioning::kCholesky;
  EquilibriumParams everyIteration = p;
  everyIteration.refactorIterations = 0;
  ASSERT_GT(p.refactorIterations, 0) << "the default keeps the factor";
  EquilibriumSolver keptSolver(p), freshSolver(everyIteration);
  const ActivationRef upperKept = kept->findActivation("upper");
  const ActivationRef upperFresh = fresh->findActivation("upper");
  int keptFactors = 0, freshFactors = 0, keptNewton = 0, freshNewton = 0;
  double tipRise = 0.0;
  const Eigen::VectorXd start = kept->state.x;
  // Frames of a rising activation, each warm-started from the last, as the integrator does.
  for (double a : {0.0, 0.1, 0.2, 0.3, 0.5, 0.52, 0.54}) {
    upperKept.model->setActivation(upperKept.index, a);
    upperFresh.model->setActivation(upperFresh.index, a);
    const EquilibriumReport rk = keptSolver.solve(*kept, kept->state.x);
    const EquilibriumReport rf = freshSolver.solve(*fresh, fresh->state.x);
    ASSERT_TRUE(rk.converged()) << a << ": " << rk.reason;
    ASSERT_TRUE(rf.converged()) << a << ": " << rf.reason;
    keptFactors += rk.factorizations, freshFactors += rf.factorizations;
    keptNewton += rk.newtonIterations, freshNewton += rf.newtonIterations;
    // Residuals below 1e-9 N at a stiffness of at least ~1 N/m: positions within 1e-9 m.
    EXPECT_LT((kept->state.x - fresh->state.x).lpNorm<Eigen::Infinity>(), 1e-9) << a;
    tipRise = kept->state.x[kept->numDofs() - 1] - start[kept->numDofs() - 1];
  }
  std::printf("factorisations %d (kept) and %d (new every iteration), Newton %d and %d\n",
              keptFactors, freshFactors, keptNewton, freshNewton);
  EXPECT_GT(tipRise, 0.0) << "the upper muscle lifts the tip";
  EXPECT_LT(keptFactors, freshFactors / 2);
}

// quasistatic takes the preconditioners of backward Euler: BoomerAMG's hierarchies, kept and
// rebuilt by the same rule as the factor, give the equilibria of Jacobi-PCG.
TEST(Equilibrium, AmgHierarchyGivesTheEquilibriaOfJacobi) {
  auto amg = muscleBeam();
  auto jacobi = muscleBeam();
  EquilibriumParams p;
  p.preconditioner = EquilibriumParams::Preconditioning::kAmg;
  EquilibriumSolver amgSolver(p), jacobiSolver(EquilibriumParams{});
  const ActivationRef upperAmg = amg->findActivation("upper");
  const ActivationRef upperJacobi = jacobi->findActivation("upper");
  int amgLinear = 0, jacobiLinear = 0, hierarchies = 0;
  for (double a : {0.0, 0.3}) {
    upperAmg.model->setActivation(upperAmg.index, a);
    upperJacobi.model->setActivation(upperJacobi.index, a);
    const EquilibriumReport ra = amgSolver.solve(*amg, amg->state.x);
    const EquilibriumReport rj = jacobiSolver.solve(*jacobi, jacobi->state.x);
    ASSERT_TRUE(ra.converged()) << a << ": " << ra.reason;
    ASSERT_TRUE(rj.converged()) << a << ": " << rj.reason;
    amgLinear += ra.linearIterations, jacobiLinear += rj.linearIterations;
    hierarchies += ra.factorizations;
    EXPECT_LT((amg->state.x - jacobi->state.x).lpNorm<Eigen::Infinity>(), 1e-9) << a;
  }
  std::printf("CG iterations %d (AMG, %d hierarchies) and %d (Jacobi)\n", amgLinear, hierarchies,
              jacobiLinear);
  EXPECT_GT(hierarchies, 0);
  EXPECT_LT(amgLinear, jacobiLinear);
}

// The line search takes the potential energy from the force pass (ForceModel::addForce returns
// it): for muscle_groups, collision and gravity it is their energy().
TEST(Equilibrium, ForcePassReturnsThePotentialEnergy) {
  auto s = muscleBeam();
  std::mt19937 rng(3);
  const ActivationRef upper = s->findActivation("upper");
  upper.model->setActivation(upper.index, 0.6);
  Eigen::VectorXd x = testutil::perturbed(s->mesh, 2e-3, rng);
  x.segment<3>(3 * (s->numNodes() - 1)).z() = 0.015;  // a node inside the plane's body
  Eigen::VectorXd f;
  const double fromForce = s->computeForce(x, Eigen::VectorXd::Zero(x.size()), f);
  const double energy = s->potentialEnergy(x);
  EXPECT_GT(std::abs(energy), 0.0);
  EXPECT_NEAR(fromForce, energy, 1e-13 * std::abs(energy));
}

// muscle_groups evaluates the total in one pass at every element's activation: it follows
// setActivation and the activation curves read at a step's start.
TEST(MuscleGroups, OnePassTotalFollowsActivationChanges) {
  std::mt19937 rng(5);
  Mesh mesh = testutil::boxMesh(2, 2, 2, 0.01, rng);
  TeranMuscleLaw::Constants k;
  k.sigmaMax = 2e5;
  std::vector<MuscleGroup> groups(2);
  groups[0].name = "a", groups[1].name = "b";
  for (int e = 0; e < mesh.numTets(); ++e) groups[e % 2].elements.push_back(e);
  groups[1].followsCurve = true;
  groups[1].curve = TimeCurve::piecewiseLinear({0.0, 1.0}, {0.0, 0.8});
  TeranMuscleLaw::Constants k1 = k;  // the box has two material ids
  k1.A = 3e4, k1.K = 2e5;
  MuscleGroupsModel model(mesh, {k, k1}, groups, LawOptions{});
  const Eigen::VectorXd x = testutil::perturbed(mesh, 8e-4, rng);
  const auto total = [&](Eigen::VectorXd& f) {
    f.setZero(x.size());
    return model.addForce(x, x, f);
  };
  const auto split = [&](double a0, double a1, Eigen::VectorXd& f) {
    f.setZero(x.size());
    Eigen::VectorXd part = Eigen::VectorXd::Zero(x.size());
    double e = model.addPassiveForce(x, f);
    const double a[2] = {a0, a1};
    for (int i = 0; i < 2; ++i) {
      part.setZero();
      e += a[i] * model.addActiveForce(i, x, part);
      f += a[i] * part;
    }
    return e;
  };
  Eigen::VectorXd f, g;
  model.setActivation(0, 0.7);
  model.beginStep(0.5, x, x);  // b: 0.4
  ASSERT_DOUBLE_EQ(model.activation(1), 0.4);
  for (int round = 0; round < 2; ++round) {
    const double e = total(f), es = split(model.activation(0), model.activation(1), g);
    EXPECT_LT(testutil::relDiff(f, g), 1e-12) << round;
    EXPECT_NEAR(e, es, 1e-12 * std::abs(es)) << round;
    EXPECT_NEAR(model.energy(x), es, 1e-12 * std::abs(es)) << round;
    model.setActivation(0, 0.1);
    model.beginStep(1.0, x, x);  // b: 0.8
  }
}

}  // namespace
}  // namespace tt
