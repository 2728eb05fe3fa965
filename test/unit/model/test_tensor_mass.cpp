// Jeffrey, "A non-linear anisotropic Finite Element Method for surgical simulation", Eqs 5-9
// with the anisotropic B of Eq 16: the linear tensor-mass tetrahedron.
#include <gtest/gtest.h>

#include <cstdio>

#include "../model_test_util.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/tensor_mass.h"

namespace tt {
namespace {

using namespace testutil;

// Sec. 1.3 calls B_jk symmetric; for j != k it is not (unless lambda = mu): B_jk = B_kj^T.
TEST(TensorMass, BlocksAreTransposedPairsNotSymmetric) {
  std::mt19937 rng(21);
  Mesh m = randomTet(rng);
  const StvkTet t = makeStvkTet(m, testMaterials(), 0);
  ASSERT_NE(t.lambda, t.mu);
  for (int j = 0; j < 4; ++j)
    for (int k = 0; k < 4; ++k) {
      const Eigen::Matrix3d Bjk = tensorMassB(t, j, k), Bkj = tensorMassB(t, k, j);
      EXPECT_LT((Bjk - Bkj.transpose()).norm(), 1e-12 * Bjk.norm());
      if (j != k) EXPECT_GT((Bjk - Bjk.transpose()).norm(), 1e-3 * Bjk.norm());
    }
}

TEST(TensorMass, StiffnessIsStvkStiffnessAtRest) {
  std::mt19937 rng(22);
  Mesh m = boxMesh(2, 2, 2, 0.01, rng);
  TensorMassModel linear(m, testMaterials());
  EdgeLengthModel stvk(m, testMaterials());
  const Eigen::VectorXd rest = restVector(m);
  const Eigen::MatrixXd Kstvk = denseStiffness(stvk, m, rest);
  EXPECT_LT(relDiff(denseStiffness(linear, m, rest), Kstvk), 1e-10);
  // Constant: the same at any x.
  EXPECT_LT(relDiff(denseStiffness(linear, m, perturbed(m, 0.003, rng)), Kstvk), 1e-10);
}

TEST(TensorMass, ForceEnergyAndStiffnessAreConsistent) {
  std::mt19937 rng(23);
  Mesh m = boxMesh(2, 1, 1, 0.01, rng);
  TensorMassModel model(m, testMaterials());
  const Eigen::VectorXd x = perturbed(m, 0.002, rng);
  const Eigen::VectorXd f = force(model, x);
  EXPECT_LT(relDiff(f, Eigen::VectorXd(-fdGradient(model, x, 1e-7))), 1e-6);
  EXPECT_LT(relDiff(denseStiffness(model, m, x), fdForceJacobian(model, x, 1e-7)), 1e-6);
  // f = -K u exactly, energy = 1/2 u^T K u.
  const Eigen::VectorXd u = x - restVector(m);
  const Eigen::MatrixXd K = denseStiffness(model, m, x);
  EXPECT_LT(relDiff(f, Eigen::VectorXd(K * u)), 1e-12);
  EXPECT_NEAR(model.energy(x), -0.5 * u.dot(K * u), 1e-12 * model.energy(x));
}

TEST(TensorMass, RestAndTranslationAreForceFree) {
  std::mt19937 rng(24);
  Mesh m = boxMesh(2, 2, 1, 0.01, rng);
  TensorMassModel model(m, testMaterials());
  const double scale = force(model, perturbed(m, 1e-4, rng)).lpNorm<Eigen::Infinity>();
  const Eigen::VectorXd rest = restVector(m);
  EXPECT_EQ(force(model, rest).lpNorm<Eigen::Infinity>(), 0.0);
  const Eigen::VectorXd moved = rigidMotion(rest, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.1, -0.2, 0.05));
  EXPECT_LT(force(model, moved).lpNorm<Eigen::Infinity>(), 1e-9 * scale);
}

// Not rotation invariant: a pure 10 degree rotation gives ghost forces comparable to a 10 %
// stretch.
TEST(TensorMass, GhostForceUnderRotation) {
  std::mt19937 rng(25);
  Mesh m = boxMesh(3, 3, 3, 0.01, rng, 0.0);
  TensorMassModel linear(m, testMaterials());
  EdgeLengthModel stvk(m, testMaterials());
  const Eigen::VectorXd rest = restVector(m);
  const Eigen::Vector3d centre = m.rest.rowwise().mean();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(10.0 * M_PI / 180.0, Eigen::Vector3d(1, 2, 3).normalized())
                                .toRotationMatrix();
  const Eigen::Matrix3d stretch = Eigen::Vector3d(1.1, 1.0, 1.0).asDiagonal();
  const Eigen::VectorXd rotated = rigidMotion(rest, R, centre - R * centre);
  const Eigen::VectorXd stretched = rigidMotion(rest, stretch, centre - stretch * centre);
  const double ghost = force(linear, rotated).norm(), stretchForce = force(linear, stretched).norm();
  const double stvkGhost = force(stvk, rotated).norm();
  std::printf("  |f| tensor_mass: 10 deg rotation %.4g N, 10%% stretch %.4g N, ratio %.3f\n", ghost,
              stretchForce, ghost / stretchForce);
  std::printf("  energy tensor_mass: rotation %.4g J, stretch %.4g J; StVK |f| under rotation %.3g N\n",
              linear.energy(rotated), linear.energy(stretched), stvkGhost);
  EXPECT_GT(ghost / stretchForce, 0.1);
  EXPECT_LT(ghost / stretchForce, 10.0);
  EXPECT_LT(stvkGhost, 1e-9 * stretchForce);
}

}  // namespace
}  // namespace tt
