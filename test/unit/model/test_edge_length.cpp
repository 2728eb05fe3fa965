// Jeffrey, "A non-linear anisotropic Finite Element Method for surgical simulation", Sec. 2
// (Eqs 20, 29, 31; the printed energy is a density and the printed force its positive
// gradient): the edge-length StVK tetrahedron, its fast (F, E, S), literal (Eq 31) and Eq 30
// paths and their shared analytic stiffness.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "../model_test_util.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace {

using namespace testutil;

TEST(EdgeLength, RestConstantsMatchGradientIdentities) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 20; ++trial) {
    Mesh m = randomTet(rng, 0.02);
    const TetRest r = tetRest(m.rest, m.tets[0]);
    const Eigen::Vector3d a0 = m.fibreFrame[0].col(0);
    const auto t = makeEdgeLengthLiteralTet(m.rest, m.tets[0], a0, testMaterials()[0]);
    const double v2 = 9.0 * r.volume * r.volume;
    const int nodes[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    for (int e = 0; e < 6; ++e) {
      const double expected = -v2 * r.grad.col(nodes[e][0]).dot(r.grad.col(nodes[e][1]));
      EXPECT_NEAR(t.K[e], expected, 1e-12 * std::abs(expected)) << "edge " << e;
    }
    for (int j = 0; j < 4; ++j) {
      const double expected = v2 * r.grad.col(j).squaredNorm();
      EXPECT_NEAR(t.areaSq[j], expected, 1e-12 * expected) << "node " << j;
      EXPECT_DOUBLE_EQ(t.fibreGrad[j], a0.dot(r.grad.col(j)));
    }
  }
}

TEST(EdgeLength, LiteralAndFastPathsAgreeOnRandomTets) {
  std::mt19937 rng(2);
  double worstForce = 0.0, worstEnergy = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    Mesh m = randomTet(rng, 0.01);
    const double amplitude = (trial % 4 == 0 ? 0.5 : 0.05) * 0.01;  // small and large strains
    const Eigen::Matrix3d R = randomRotation(rng);  // before the perturbation, as g++ drew them
    Eigen::VectorXd x = rigidMotion(perturbed(m, amplitude, rng), R, Eigen::Vector3d(0.01, -0.02, 0.03));
    EdgeLengthModel fast(m, testMaterials(), EdgeLengthPath::kFast);
    EdgeLengthModel literal(m, testMaterials(), EdgeLengthPath::kLiteral);
    worstForce = std::max(worstForce, relDiff(force(literal, x), force(fast, x)));
    worstEnergy = std::max(worstEnergy,
                           std::abs(literal.energy(x) - fast.energy(x)) / fast.energy(x));
  }
  EXPECT_LT(worstForce, 1e-10);
  EXPECT_LT(worstEnergy, 1e-10);
}

// Eq 30 (two sums, line 4's K_jkm read as K_jkmp) against Eq 31 (one sum) and the fast path:
// per tet on random rest shapes, small and large strains, rotated and translated, and with
// the fibre coefficient of both signs (lambda^L, mu^L above and below lambda, mu).
TEST(EdgeLength, Eq30AgreesWithEq31AndTheFastPathOnRandomTets) {
  std::mt19937 rng(12);
  const std::vector<std::vector<Material>> materialSets = {
      testMaterials(), {Material::transverselyIsotropic(1.2e5, 0.35, 3e4, 0.3, 1e3)}};
  double worst31 = 0.0, worstFast = 0.0, worstEnergy = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    Mesh m = randomTet(rng, 0.01);
    const std::vector<Material>& mats = materialSets[trial % 2];
    const double amplitude = (trial % 4 == 0 ? 0.5 : 0.05) * 0.01;
    const Eigen::Matrix3d R = randomRotation(rng);  // before the perturbation, as g++ drew them
    const Eigen::VectorXd x =
        rigidMotion(perturbed(m, amplitude, rng), R, Eigen::Vector3d(0.01, -0.02, 0.03));
    EdgeLengthModel fast(m, mats, EdgeLengthPath::kFast);
    EdgeLengthModel eq31(m, mats, EdgeLengthPath::kLiteral);
    EdgeLengthModel eq30(m, mats, EdgeLengthPath::kEq30);
    Eigen::VectorXd f30 = Eigen::VectorXd::Zero(12), f31 = f30, ff = f30;
    const double e30 = eq30.addForce(x, x, f30), e31 = eq31.addForce(x, x, f31);
    const double ef = fast.addForce(x, x, ff);
    worst31 = std::max(worst31, relDiff(f30, f31));
    worstFast = std::max(worstFast, relDiff(f30, ff));
    worstEnergy = std::max({worstEnergy, std::abs(e30 - ef) / ef, std::abs(e30 - e31) / ef,
                            std::abs(eq30.energy(x) - ef) / ef});
  }
  EXPECT_LT(worst31, 1e-12);
  EXPECT_LT(worstFast, 1e-10);
  EXPECT_LT(worstEnergy, 1e-10);
}

TEST(EdgeLength, LiteralAndFastPathsAgreeOnAMesh) {
  std::mt19937 rng(3);
  Mesh m = boxMesh(3, 2, 2, 0.01, rng);
  const Eigen::VectorXd x = perturbed(m, 0.001, rng);
  EdgeLengthModel fast(m, testMaterials(), EdgeLengthPath::kFast);
  EdgeLengthModel literal(m, testMaterials(), EdgeLengthPath::kLiteral);
  Eigen::VectorXd ff = Eigen::VectorXd::Zero(x.size()), fl = ff;
  const double ef = fast.addForce(x, x, ff), el = literal.addForce(x, x, fl);
  EXPECT_LT(relDiff(fl, ff), 1e-10);
  EXPECT_NEAR(el, ef, 1e-10 * ef);
  EXPECT_NEAR(ef, fast.energy(x), 1e-14 * ef);   // addForce returns the energy too
  EXPECT_NEAR(el, literal.energy(x), 1e-14 * el);
}

class EdgeLengthPaths : public ::testing::TestWithParam<EdgeLengthPath> {};

TEST_P(EdgeLengthPaths, ForceIsMinusEnergyGradient) {
  std::mt19937 rng(4);
  Mesh m = boxMesh(2, 2, 1, 0.01, rng);
  EdgeLengthModel model(m, testMaterials(), GetParam());
  const Eigen::VectorXd x = perturbed(m, 0.002, rng);
  const Eigen::VectorXd grad = fdGradient(model, x, 1e-7);
  EXPECT_LT(relDiff(force(model, x), Eigen::VectorXd(-grad)), 1e-6);
}

TEST_P(EdgeLengthPaths, StiffnessIsForceJacobian) {
  std::mt19937 rng(5);
  Mesh m = boxMesh(2, 1, 1, 0.01, rng);
  EdgeLengthModel model(m, testMaterials(), GetParam());
  const Eigen::VectorXd x = perturbed(m, 0.002, rng);
  const Eigen::MatrixXd K = denseStiffness(model, m, x);
  EXPECT_LT(relDiff(K, fdForceJacobian(model, x, 1e-7)), 1e-6);
  EXPECT_LT(relDiff(K, Eigen::MatrixXd(K.transpose())), 1e-13);  // conservative: symmetric
}

TEST_P(EdgeLengthPaths, ZeroForceAtRest) {
  std::mt19937 rng(6);
  Mesh m = boxMesh(2, 2, 2, 0.01, rng);
  EdgeLengthModel model(m, testMaterials(), GetParam());
  const Eigen::VectorXd rest = restVector(m);
  // Force scale: 1% strain.
  const double scale = force(model, perturbed(m, 1e-4, rng)).lpNorm<Eigen::Infinity>();
  EXPECT_LT(force(model, rest).lpNorm<Eigen::Infinity>(), 1e-10 * scale);
  EXPECT_LT(std::abs(model.energy(rest)), 1e-20);
}

TEST_P(EdgeLengthPaths, RigidMotionLeavesEnergyAndRotatesForces) {
  std::mt19937 rng(7);
  Mesh m = boxMesh(2, 2, 1, 0.01, rng);
  EdgeLengthModel model(m, testMaterials(), GetParam());
  const Eigen::VectorXd x = perturbed(m, 0.002, rng);
  const Eigen::Matrix3d R = randomRotation(rng);
  const Eigen::VectorXd y = rigidMotion(x, R, Eigen::Vector3d(0.05, 0.02, -0.03));
  EXPECT_NEAR(model.energy(y), model.energy(x), 1e-11 * model.energy(x));
  EXPECT_LT(relDiff(force(model, y), rotateVectors(force(model, x), R)), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(AllPaths, EdgeLengthPaths,
                         ::testing::Values(EdgeLengthPath::kFast, EdgeLengthPath::kLiteral,
                                           EdgeLengthPath::kEq30));

// Energy of a 5% uniaxial stretch of a single tet along direction n.
double stretchEnergy(const Mesh& m, const std::vector<Material>& mats, EdgeLengthPath path,
                     const Eigen::Vector3d& n) {
  EdgeLengthModel model(m, mats, path);
  const Eigen::Matrix3d F = Eigen::Matrix3d::Identity() + 0.05 * n * n.transpose();
  Eigen::VectorXd x(12);
  for (int p = 0; p < 4; ++p) x.segment<3>(3 * p) = F * m.rest.col(p);
  return model.energy(x);
}

TEST(EdgeLength, StretchAlongFibreCostsMoreWhenELExceedsET) {
  std::mt19937 rng(8);
  for (EdgeLengthPath path : {EdgeLengthPath::kFast, EdgeLengthPath::kLiteral, EdgeLengthPath::kEq30}) {
    Mesh m = randomTet(rng);
    const Eigen::Vector3d along = m.fibreFrame[0].col(0), across = m.fibreFrame[0].col(1);
    const std::vector<Material> aniso = {Material::transverselyIsotropic(3e4, 0.3, 1.2e5, 0.3, 1e3)};
    const std::vector<Material> iso = {Material::isotropic(3e4, 0.3, 1e3)};
    const double eAlong = stretchEnergy(m, aniso, path, along);
    const double eAcross = stretchEnergy(m, aniso, path, across);
    EXPECT_GT(eAlong, 1.5 * eAcross);
    // The isotropic material does not see the fibre.
    EXPECT_NEAR(stretchEnergy(m, iso, path, along), stretchEnergy(m, iso, path, across),
                1e-10 * eAcross);
    // The fibre term adds exactly c (a0^T E a0)^2 V0 to the along-fibre stretch.
    const double fibreStrain = 0.05 + 0.5 * 0.05 * 0.05;
    EXPECT_NEAR(eAlong - stretchEnergy(m, iso, path, along),
                aniso[0].elasticConstants().fibreCoefficient() * fibreStrain * fibreStrain * tetVolume(m.rest, m.tets[0]),
                1e-9 * eAlong);
  }
}

// The largest eigenvalue of the stiffness dF/dx (the energy Hessian's is minus it) relative to
// the largest magnitude: > 0 where the Hessian is indefinite.
double largestStiffnessEigenvalue(const Eigen::MatrixXd& K) {
  const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (K + K.transpose())).eigenvalues();
  return eig.maxCoeff() / eig.cwiseAbs().maxCoeff();
}

TEST(EdgeLength, PsdProjectionMakesTheCompressedStiffnessPositiveSemiDefinite) {
  std::mt19937 rng(8);
  int indefinite = 0;
  for (int trial = 0; trial < 20; ++trial) {
    Mesh m = boxMesh(2, 1, 1, 0.01, rng);
    // Compressed to 70 % about the centre, rotated and a little perturbed: S negative there.
    Eigen::VectorXd x = perturbed(m, 0.0003, rng);
    const Eigen::Vector3d centre = m.rest.rowwise().mean();
    for (int a = 0; a < m.numNodes(); ++a) x.segment<3>(3 * a) = centre + 0.7 * (x.segment<3>(3 * a) - centre);
    x = rigidMotion(x, randomRotation(rng), Eigen::Vector3d(0.01, 0.02, -0.01));
    const EdgeLengthModel exact(m, testMaterials()), projected(m, testMaterials(), EdgeLengthPath::kFast, true);
    indefinite += largestStiffnessEigenvalue(denseStiffness(exact, m, x)) > 1e-8;
    EXPECT_LT(largestStiffnessEigenvalue(denseStiffness(projected, m, x)), 1e-12) << "trial " << trial;
    EXPECT_EQ(relDiff(force(projected, x), force(exact, x)), 0.0);  // only the matrix changes
  }
  EXPECT_EQ(indefinite, 20);  // the projection had work to do in every trial
}

TEST(EdgeLength, PsdProjectionLeavesAStretchedTetsStiffnessAlone) {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 10; ++trial) {
    Mesh m = randomTet(rng, 0.01);
    // Stretched by 20 % about the first node and rotated: S positive definite, and the test
    // materials' fibre coefficients are positive, so the Hessian is already PSD.
    Eigen::VectorXd x = restVector(m);
    for (int a = 1; a < 4; ++a) x.segment<3>(3 * a) = m.rest.col(0) + 1.2 * (m.rest.col(a) - m.rest.col(0));
    x = rigidMotion(x, randomRotation(rng), Eigen::Vector3d(-0.02, 0.01, 0.0));
    const EdgeLengthModel exact(m, testMaterials()), projected(m, testMaterials(), EdgeLengthPath::kFast, true);
    const Eigen::MatrixXd K = denseStiffness(exact, m, x);
    EXPECT_LT(relDiff(denseStiffness(projected, m, x), K), 1e-14) << "trial " << trial;
    EXPECT_LT(largestStiffnessEigenvalue(K), 1e-12);
  }
}

TEST(EdgeLength, PathNamesParse) {
  EdgeLengthPath p;
  ASSERT_TRUE(parseEdgeLengthPath("literal", p));
  EXPECT_EQ(p, EdgeLengthPath::kLiteral);
  ASSERT_TRUE(parseEdgeLengthPath("eq30", p));
  EXPECT_EQ(p, EdgeLengthPath::kEq30);
  ASSERT_TRUE(parseEdgeLengthPath("fast", p));
  EXPECT_EQ(p, EdgeLengthPath::kFast);
  EXPECT_FALSE(parseEdgeLengthPath("Fast ", p));
}

// A scene selects the Eq 30 path the way it selects the literal one: edge_length {path: eq30}.
TEST(EdgeLength, SceneKeySelectsEachPath) {
  std::mt19937 rng(13);
  const Mesh m = boxMesh(1, 1, 1, 0.01, rng);
  const std::string origin = "test_edge_length";
  for (const auto& [name, expected] : {std::pair<std::string, EdgeLengthPath>{"fast", EdgeLengthPath::kFast},
                                       {"literal", EdgeLengthPath::kLiteral},
                                       {"eq30", EdgeLengthPath::kEq30}}) {
    const YAML::Node spec = YAML::Load("{type: edge_length, path: " + name + "}");
    const auto model = registry().makeForceModel(YamlEntry(spec, "", &origin),
                                                 ModelContext{m, testMaterials(), {}});
    EXPECT_EQ(dynamic_cast<const EdgeLengthModel&>(*model).path(), expected) << name;
  }
}

}  // namespace
}  // namespace tt
