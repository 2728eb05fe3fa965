// The force model collision (model/collision.h): penalty eps d n out of planes, spheres and
// closed triangle surfaces (Bao, "Derivation of Quasistatics and Landmark Optimization for
// Muscles", Sec. 5.7). The surface's signed distance against the exact one of a box, forces
// against energies and stiffnesses against forces by central differences, no force outside,
// the push of a node inside along the right normal by eps times its depth.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "../model_test_util.h"
#include "tissue_trainer/core/model/collision.h"
#include "../random_draws.h"

namespace tt {
namespace {

using testutil::relDiff;

// The box [0, s]^3 as 12 outward triangles.
ClosedSurface cube(double s, bool inward = false) {
  Eigen::Matrix3Xd v(3, 8);
  v << 0, 1, 1, 0, 0, 1, 1, 0,  //
      0, 0, 1, 1, 0, 0, 1, 1,   //
      0, 0, 0, 0, 1, 1, 1, 1;
  std::vector<Triangle> t = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                             {3, 7, 6}, {3, 6, 2}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
  if (inward)
    for (Triangle& tri : t) std::swap(tri[1], tri[2]);
  return ClosedSurface(s * v, t);
}

// The exact signed distance to the box [0, s]^3.
double boxDistance(const Eigen::Vector3d& x, double s) {
  const Eigen::Vector3d q = (x - Eigen::Vector3d::Constant(s / 2)).cwiseAbs() -
                            Eigen::Vector3d::Constant(s / 2);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

TEST(ClosedSurface, SignedDistanceOfACubeIsExactEverywhere) {
  for (bool inward : {false, true}) {
    const ClosedSurface surface = cube(0.02, inward);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-0.015, 0.035);
    int inside = 0;
    for (int k = 0; k < 4000; ++k) {
      const Eigen::Vector3d x = testutil::drawVector(u, rng);
      Eigen::Vector3d nearest;
      const double d = surface.signedDistance(x, nearest);
      ASSERT_NEAR(d, boxDistance(x, 0.02), 1e-15) << x.transpose();
      EXPECT_NEAR((x - nearest).norm(), std::abs(d), 1e-15);
      Penetration p;
      EXPECT_EQ(surface.inside(x, p), d < 0.0) << x.transpose();
      inside += d < 0.0;
    }
    EXPECT_GT(inside, 200);  // the sample covers both sides
  }
}

TEST(ClosedSurface, OpenOrInconsistentSurfacesAreRejected) {
  Eigen::Matrix3Xd v(3, 4);
  v << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  const std::vector<Triangle> tetFaces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  EXPECT_NO_THROW(ClosedSurface(v, tetFaces));
  EXPECT_THROW(ClosedSurface(v, {tetFaces[0], tetFaces[1], tetFaces[2]}), std::invalid_argument);
  std::vector<Triangle> flipped = tetFaces;
  std::swap(flipped[3][1], flipped[3][2]);
  EXPECT_THROW(ClosedSurface(v, flipped), std::invalid_argument);
}

struct Bodies {
  std::vector<CollisionBody> bodies;
  std::vector<ClosedSurface> surfaces;
};

Bodies threeBodies() {
  Bodies b;
  b.bodies.push_back(CollisionBody::plane(Eigen::Vector3d(0, 0, 0.001), Eigen::Vector3d(0.2, 0.1, 1)));
  b.bodies.push_back(CollisionBody::sphere(Eigen::Vector3d(0.02, 0.02, 0.02), 0.012));
  b.surfaces.push_back(cube(0.01));
  CollisionBody mesh;
  mesh.kind = CollisionBody::Kind::kMesh;
  mesh.surface = 0;
  mesh.point = Eigen::Vector3d::Zero();
  b.bodies.push_back(mesh);
  return b;
}

// Nodes of a 2 x 2 x 2 box (for its sparse pattern) moved to random places near the bodies.
TEST(CollisionModel, ForceIsMinusEnergyGradientAndStiffnessItsDerivative) {
  std::mt19937 rng(2);
  const Mesh mesh = testutil::boxMesh(2, 2, 2, 0.01, rng);
  std::vector<int> nodes(mesh.numNodes());
  for (int i = 0; i < mesh.numNodes(); ++i) nodes[i] = i;
  for (bool psd : {false, true}) {
    Bodies b = threeBodies();
    const CollisionModel model(mesh.numNodes(), nodes, 800.0, b.bodies, b.surfaces, psd);
    std::uniform_real_distribution<double> u(-0.004, 0.03);
    Eigen::VectorXd x(3 * mesh.numNodes());
    for (int i = 0; i < x.size(); ++i) x[i] = u(rng);
    const Eigen::VectorXd f = testutil::force(model, x);
    int pushed = 0;
    for (int n = 0; n < mesh.numNodes(); ++n) pushed += f.segment<3>(3 * n).norm() > 0.0;
    EXPECT_GT(pushed, 4);
    EXPECT_LT(relDiff(f, Eigen::VectorXd(-testutil::fdGradient(model, x, 1e-8))), 1e-6);
    const Eigen::MatrixXd K = testutil::denseStiffness(model, mesh, x);
    const Eigen::VectorXd d = Eigen::VectorXd::Random(x.size());
    Eigen::VectorXd Kd = Eigen::VectorXd::Zero(x.size());
    model.addStiffnessTimes(x, d, 1.0, Kd);
    EXPECT_LT(relDiff(Kd, Eigen::VectorXd(K * d)), 1e-14);
    if (!psd) {
      EXPECT_LT(relDiff(K, testutil::fdForceJacobian(model, x, 1e-8)), 1e-6);
    } else {
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(-K);
      EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-12 * 800.0);
    }
  }
}

TEST(CollisionModel, NoForceOutsideTheBodies) {
  std::mt19937 rng(6);
  const Mesh mesh = testutil::boxMesh(2, 2, 2, 0.01, rng);
  std::vector<int> nodes(mesh.numNodes());
  for (int i = 0; i < mesh.numNodes(); ++i) nodes[i] = i;
  Bodies b = threeBodies();
  const CollisionModel model(mesh.numNodes(), nodes, 800.0, b.bodies, b.surfaces, false);
  // Above the plane, outside the cube and the sphere: x in [0.012, 0.014], z > 0.004.
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::VectorXd x(3 * mesh.numNodes());
  for (int n = 0; n < mesh.numNodes(); ++n)
    x.segment<3>(3 * n) << 0.012 + 0.002 * u(rng), 0.002 * u(rng), 0.004 + 0.003 * u(rng);
  EXPECT_EQ(testutil::force(model, x).lpNorm<Eigen::Infinity>(), 0.0);
  EXPECT_EQ(model.energy(x), 0.0);
  EXPECT_EQ(testutil::denseStiffness(model, mesh, x).lpNorm<Eigen::Infinity>(), 0.0);
}

// One node inside one body: the force is eps d along the outward normal, d the depth.
TEST(CollisionModel, ANodeInsideIsPushedOutAlongTheNormal) {
  const double eps = 500.0;
  Mesh one;
  one.rest = Eigen::Matrix3Xd::Zero(3, 1);
  one.fillDefaults();
  auto forceOn = [&](CollisionBody body, std::vector<ClosedSurface> surfaces,
                     const Eigen::Vector3d& x) {
    const CollisionModel model(1, {0}, eps, {body}, std::move(surfaces), false);
    return Eigen::Vector3d(testutil::force(model, Eigen::VectorXd(x)));
  };
  // Plane through (0, 0, 1) with normal (0, 0.6, 0.8): x = (3, -1, 0.2) is 0.8 * 0.8 + 0.6 = 1.24 behind.
  const Eigen::Vector3d planeNormal(0, 0.6, 0.8);
  const Eigen::Vector3d fp = forceOn(CollisionBody::plane(Eigen::Vector3d(0, 0, 1), planeNormal * 5.0),
                                     {}, Eigen::Vector3d(3, -1, 0.2));
  EXPECT_LT((fp - eps * 1.24 * planeNormal).norm(), 1e-12);
  // Sphere at (1, 2, 3), radius 2: x = c + (0.6, 0, -0.8) is at distance 1, depth 1.
  const Eigen::Vector3d fs = forceOn(CollisionBody::sphere(Eigen::Vector3d(1, 2, 3), 2.0), {},
                                     Eigen::Vector3d(1.6, 2, 2.2));
  EXPECT_LT((fs - eps * Eigen::Vector3d(0.6, 0, -0.8)).norm(), 1e-12);
  // Cube [0, 1]^3: x = (0.3, 0.9, 0.5) is 0.1 below its face y = 1.
  CollisionBody mesh;
  mesh.kind = CollisionBody::Kind::kMesh;
  mesh.surface = 0;
  const Eigen::Vector3d fm = forceOn(mesh, {cube(1.0)}, Eigen::Vector3d(0.3, 0.9, 0.5));
  EXPECT_LT((fm - eps * Eigen::Vector3d(0, 0.1, 0)).norm(), 1e-12);
  // Outside each: nothing.
  EXPECT_EQ(forceOn(CollisionBody::sphere(Eigen::Vector3d(1, 2, 3), 2.0), {},
                    Eigen::Vector3d(1, 2, 5.0001)).norm(), 0.0);
  EXPECT_EQ(forceOn(mesh, {cube(1.0)}, Eigen::Vector3d(1.05, 1.05, 0.5)).norm(), 0.0);
}

}  // namespace
}  // namespace tt
