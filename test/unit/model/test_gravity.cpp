// Lumped gravity: f_i = m_i g, energy -m g . x, zero stiffness.
#include <gtest/gtest.h>

#include "../model_test_util.h"
#include "tissue_trainer/core/model/gravity.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace {

using namespace testutil;

TEST(Gravity, ForceIsLumpedWeightAndMinusEnergyGradient) {
  std::mt19937 rng(31);
  Mesh m = boxMesh(2, 2, 1, 0.01, rng);
  const std::vector<Material> mats = testMaterials();
  System system(m, mats);
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  GravityModel gravity(system.mass, g);
  const Eigen::VectorXd x = perturbed(m, 0.003, rng);
  const Eigen::VectorXd f = force(gravity, x);

  double totalMass = 0.0;  // sum of rho V0 over tets
  for (int e = 0; e < m.numTets(); ++e)
    totalMass += mats[m.material[e]].density * tetVolume(m.rest, m.tets[e]);
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int i = 0; i < m.numNodes(); ++i) total += f.segment<3>(3 * i);
  EXPECT_LT((total - totalMass * g).norm(), 1e-12 * totalMass * g.norm());
  EXPECT_EQ(f[3 * 1 + 0], 0.0);
  EXPECT_DOUBLE_EQ(f[3 * 1 + 2], system.mass[3 * 1 + 2] * g.z());

  EXPECT_LT(relDiff(f, Eigen::VectorXd(-fdGradient(gravity, x, 1e-4))), 1e-9);
  // Lifting the body by h along -g costs M |g| h.
  const Eigen::VectorXd lifted = rigidMotion(x, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.2));
  EXPECT_NEAR(gravity.energy(lifted) - gravity.energy(x), totalMass * 9.81 * 0.2, 1e-12);
  EXPECT_TRUE(gravity.hasStiffness());
  EXPECT_EQ(denseStiffness(gravity, m, x).norm(), 0.0);
}

}  // namespace
}  // namespace tt
