// The force model muscle_groups (model/muscle_groups.h): the force is f_0 + sum_i a_i f_i to
// round-off (Bao, "Derivation of Quasistatics and Landmark Optimization for Muscles", Eq. 4),
// each part's force against its energy and its stiffness against its force by central
// differences, no force at rest without activation, and the active stress at rest by hand.
#include <gtest/gtest.h>

#include <random>

#include "../model_test_util.h"
#include "tissue_trainer/core/model/muscle_groups.h"

namespace tt {
namespace {

using testutil::relDiff;

struct Fixture {
  Mesh mesh;
  std::vector<TeranMuscleLaw::Constants> constants;
  std::vector<MuscleGroup> groups;
};

// A jittered 2 x 2 x 2 box with two materials and three muscles over part of its elements
// (the rest is passive), each with its own fibre direction.
Fixture makeFixture(std::mt19937& rng, bool deviatoric) {
  Fixture f;
  f.mesh = testutil::boxMesh(2, 2, 2, 0.01, rng);
  TeranMuscleLaw::Constants a, b;
  a.sigmaMax = 2e5;
  b.A = 3e4, b.B = 1e4, b.K = 2e5, b.sigmaMax = 1e5;
  a.deviatoricStretch = b.deviatoricStretch = deviatoric;
  f.constants = {a, b};
  const Eigen::Vector3d directions[3] = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 1),
                                         Eigen::Vector3d(-1, 2, 0.5)};
  const int count = f.mesh.numTets();
  for (int g = 0; g < 3; ++g) {
    MuscleGroup group;
    group.name = "muscle" + std::to_string(g);
    for (int e = g; e < count - 5; e += 3) {
      group.elements.push_back(e);
      f.mesh.fibreFrame[e] = testutil::frameFrom(directions[g]);
    }
    f.groups.push_back(group);
  }
  return f;
}

Eigen::VectorXd activeForce(const MuscleGroupsModel& m, int i, const Eigen::VectorXd& x) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  m.addActiveForce(i, x, f);
  return f;
}

Eigen::MatrixXd activeStiffness(const MuscleGroupsModel& m, int i, const Mesh& mesh,
                                const Eigen::VectorXd& x) {
  const SparsePattern pattern = meshPattern(mesh);
  SparseMatrix K = pattern.zeroMatrix();
  if (i < 0)
    m.addPassiveStiffness(x, 1.0, pattern, K);
  else
    m.addActiveStiffness(i, x, 1.0, pattern, K);
  return Eigen::MatrixXd(K);
}

TEST(MuscleGroups, ForceIsPassivePlusActivationsTimesActiveForces) {
  for (bool deviatoric : {true, false}) {
    std::mt19937 rng(11);
    Fixture fx = makeFixture(rng, deviatoric);
    MuscleGroupsModel model(fx.mesh, fx.constants, fx.groups, LawOptions{});
    const double a[3] = {0.7, 0.0, 0.35};
    for (int i = 0; i < 3; ++i) model.setActivation(i, a[i]);
    const Eigen::VectorXd x = testutil::perturbed(fx.mesh, 8e-4, rng);

    Eigen::VectorXd split = Eigen::VectorXd::Zero(x.size());
    double splitEnergy = model.addPassiveForce(x, split);
    for (int i = 0; i < 3; ++i) {
      const Eigen::VectorXd fi = activeForce(model, i, x);
      EXPECT_GT(fi.norm(), 0.0) << i;
      split += a[i] * fi;
      Eigen::VectorXd unused = Eigen::VectorXd::Zero(x.size());
      splitEnergy += a[i] * model.addActiveForce(i, x, unused);
    }
    const Eigen::VectorXd f = testutil::force(model, x);
    EXPECT_LT(relDiff(f, split), 1e-13) << deviatoric;
    EXPECT_NEAR(model.energy(x), splitEnergy, 1e-13 * std::abs(splitEnergy));

    // The same with the law's own activation: one hyperelastic model per activation pattern.
    std::vector<TeranMuscleLaw::Constants> k = fx.constants;
    Mesh relabelled = fx.mesh;
    for (int g = 0; g < 3; ++g)
      for (int e : fx.groups[g].elements) {
        relabelled.material[e] = static_cast<int>(k.size());
        TeranMuscleLaw::Constants c = fx.constants[fx.mesh.material[e]];
        c.activation = a[g];
        k.push_back(c);
      }
    const HyperelasticModel<TeranMuscleLaw> reference(relabelled, k, LawOptions{});
    EXPECT_LT(relDiff(f, testutil::force(reference, x)), 1e-12) << deviatoric;

    Eigen::MatrixXd Ksplit = activeStiffness(model, -1, fx.mesh, x);
    for (int i = 0; i < 3; ++i) Ksplit += a[i] * activeStiffness(model, i, fx.mesh, x);
    EXPECT_LT(relDiff(testutil::denseStiffness(model, fx.mesh, x), Ksplit), 1e-13);
  }
}

// With inversion handling every part is evaluated at the same clamped F, where the law is still
// linear in alpha: the split holds on an inverted tet too.
TEST(MuscleGroups, SplitHoldsOnAnInvertedElementWithInversionHandling) {
  std::mt19937 rng(21);
  Fixture fx = makeFixture(rng, true);
  LawOptions options;
  options.inversionThreshold = 0.25;
  MuscleGroupsModel model(fx.mesh, fx.constants, fx.groups, options);
  const double a[3] = {0.4, 0.9, 0.15};
  for (int i = 0; i < 3; ++i) model.setActivation(i, a[i]);
  Eigen::VectorXd x = testutil::perturbed(fx.mesh, 3e-4, rng);
  // Mirror node 0 of a tet of muscle 0 through the plane of its other three nodes.
  const Tet& t = fx.mesh.tets[fx.groups[0].elements[1]];
  const Eigen::Vector3d p1 = x.segment<3>(3 * t[1]), p2 = x.segment<3>(3 * t[2]),
                        p3 = x.segment<3>(3 * t[3]);
  const Eigen::Vector3d n = (p2 - p1).cross(p3 - p1).normalized();
  x.segment<3>(3 * t[0]) -= 2.0 * n.dot(x.segment<3>(3 * t[0]) - p1) * n;
  Eigen::Matrix3Xd deformed = Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, fx.mesh.numNodes());
  ASSERT_LT(tetVolume(deformed, t), 0.0);

  Eigen::VectorXd split = Eigen::VectorXd::Zero(x.size());
  model.addPassiveForce(x, split);
  for (int i = 0; i < 3; ++i) split += a[i] * activeForce(model, i, x);
  const Eigen::VectorXd f = testutil::force(model, x);
  EXPECT_TRUE(f.allFinite());
  EXPECT_LT(relDiff(f, split), 1e-13);
}

TEST(MuscleGroups, EachPartsForceIsMinusItsEnergyGradientAndStiffnessItsDerivative) {
  std::mt19937 rng(5);
  Fixture fx = makeFixture(rng, true);
  MuscleGroupsModel model(fx.mesh, fx.constants, fx.groups, LawOptions{});
  const Eigen::VectorXd x = testutil::perturbed(fx.mesh, 6e-4, rng);
  const double h = 1e-7;
  for (int i = -1; i < 3; ++i) {
    auto partForce = [&](const Eigen::VectorXd& y, double* energy) {
      Eigen::VectorXd f = Eigen::VectorXd::Zero(y.size());
      const double e = i < 0 ? model.addPassiveForce(y, f) : model.addActiveForce(i, y, f);
      if (energy) *energy = e;
      return f;
    };
    Eigen::VectorXd gradient(x.size());
    Eigen::MatrixXd jacobian(x.size(), x.size());
    Eigen::VectorXd y = x;
    for (int d = 0; d < x.size(); ++d) {
      double ep, em;
      y[d] = x[d] + h;
      const Eigen::VectorXd fp = partForce(y, &ep);
      y[d] = x[d] - h;
      const Eigen::VectorXd fm = partForce(y, &em);
      y[d] = x[d];
      gradient[d] = (ep - em) / (2 * h);
      jacobian.col(d) = (fp - fm) / (2 * h);
    }
    EXPECT_LT(relDiff(Eigen::VectorXd(-gradient), partForce(x, nullptr)), 1e-6) << "part " << i;
    EXPECT_LT(relDiff(activeStiffness(model, i, fx.mesh, x), jacobian), 1e-6) << "part " << i;
  }
  // The whole model at activations: force, stiffness and stiffness product.
  for (int i = 0; i < 3; ++i) model.setActivation(i, 0.2 + 0.3 * i);
  EXPECT_LT(relDiff(testutil::force(model, x), Eigen::VectorXd(-testutil::fdGradient(model, x, h))), 1e-6);
  const Eigen::MatrixXd K = testutil::denseStiffness(model, fx.mesh, x);
  EXPECT_LT(relDiff(K, testutil::fdForceJacobian(model, x, h)), 1e-6);
  const Eigen::VectorXd d = testutil::perturbed(fx.mesh, 1.0, rng) - testutil::restVector(fx.mesh);
  Eigen::VectorXd Kd = Eigen::VectorXd::Zero(x.size());
  model.addStiffnessTimes(x, d, 1.0, Kd);
  EXPECT_LT(relDiff(Kd, Eigen::VectorXd(K * d)), 1e-12);
}

TEST(MuscleGroups, NoForceAtRestWithoutActivation) {
  std::mt19937 rng(3);
  Fixture fx = makeFixture(rng, true);
  MuscleGroupsModel model(fx.mesh, fx.constants, fx.groups, LawOptions{});
  const Eigen::VectorXd rest = testutil::restVector(fx.mesh);
  EXPECT_LT(testutil::force(model, rest).lpNorm<Eigen::Infinity>(), 1e-9);
  model.setActivation(1, 0.5);  // an activated muscle pulls at rest: t_a(1) = 1
  EXPECT_GT(testutil::force(model, rest).lpNorm<Eigen::Infinity>(), 1.0);
}

// At rest the active stress of a muscle with fibre a0 is P = sigma_max (a0 a0^T - I/3)
// (deviatoric stretch) or sigma_max a0 a0^T, and sum_p f_p x_p^T = -V P over its elements,
// V their volume: the muscle pulls its nodes together along its own fibre only.
TEST(MuscleGroups, TwoMusclesContractAlongTheirOwnFibres) {
  for (bool deviatoric : {true, false}) {
    std::mt19937 rng(8);
    Fixture fx = makeFixture(rng, deviatoric);
    fx.constants[1] = fx.constants[0];  // one sigma_max for the whole muscle
    MuscleGroupsModel model(fx.mesh, fx.constants, fx.groups, LawOptions{});
    const Eigen::VectorXd rest = testutil::restVector(fx.mesh);
    for (int i = 0; i < 2; ++i) {
      const Eigen::VectorXd f = activeForce(model, i, rest);
      Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
      for (int n = 0; n < fx.mesh.numNodes(); ++n)
        moment += f.segment<3>(3 * n) * fx.mesh.rest.col(n).transpose();
      double volume = 0.0;
      for (int e : fx.groups[i].elements) volume += tetVolume(fx.mesh.rest, fx.mesh.tets[e]);
      const Eigen::Vector3d a0 = fx.mesh.fibreFrame[fx.groups[i].elements[0]].col(0);
      Eigen::Matrix3d P = a0 * a0.transpose();
      if (deviatoric) P -= Eigen::Matrix3d::Identity() / 3.0;
      const Eigen::Matrix3d expected = -volume * fx.constants[0].sigmaMax * P;
      EXPECT_LT((moment - expected).norm(), 1e-10 * expected.norm()) << i << " " << deviatoric;
      EXPECT_LT(a0.dot(moment * a0), 0.0);  // a pull along its fibre
    }
  }
}

TEST(MuscleGroups, RejectsOverlapsDuplicatesAndActivationsOutsideTheRange) {
  std::mt19937 rng(1);
  Fixture fx = makeFixture(rng, true);
  auto build = [&](std::vector<MuscleGroup> g) {
    MuscleGroupsModel(fx.mesh, fx.constants, std::move(g), LawOptions{});
  };
  std::vector<MuscleGroup> g = fx.groups;
  g[1].elements.push_back(g[0].elements[0]);
  EXPECT_THROW(build(g), std::invalid_argument);
  g = fx.groups;
  g[2].name = g[0].name;
  EXPECT_THROW(build(g), std::invalid_argument);
  g = fx.groups;
  g[0].activation = 1.5;
  EXPECT_THROW(build(g), std::invalid_argument);
  g = fx.groups;
  g[1].elements.clear();
  EXPECT_THROW(build(g), std::invalid_argument);
  MuscleGroupsModel model(fx.mesh, fx.constants, fx.groups, LawOptions{});
  EXPECT_THROW(model.setActivation(0, -0.1), std::invalid_argument);
  EXPECT_EQ(model.groupIndex("muscle2"), 2);
  EXPECT_EQ(model.groupIndex("nope"), -1);
}

}  // namespace
}  // namespace tt
