#include <gtest/gtest.h>

#include "tissue_trainer/core/system.h"

namespace tt {
namespace {

Mesh unitTet() {
  Mesh m;
  m.rest.resize(3, 4);
  m.rest << 0, 1, 0, 0,
            0, 0, 1, 0,
            0, 0, 0, 1;
  m.tets = {{0, 1, 2, 3}};
  m.fillDefaults();
  return m;
}

TEST(System, LumpedMassIsAQuarterOfEachTetMass) {
  Material steelish = Material::isotropic(1e5, 0.3, 1200.0);
  System s(unitTet(), {steelish});
  const double tetMass = 1200.0 / 6.0;
  for (int dof = 0; dof < 12; ++dof) EXPECT_DOUBLE_EQ(s.mass[dof], tetMass / 4.0);
}

TEST(System, FixedAndControlledNodesArePrescribed) {
  Mesh m = unitTet();
  m.nodeTags[0] = kFixedAll;
  m.nodeTags[1] = kFixedZ;
  System s(m, {Material::isotropic(1e5, 0.3, 1000.0)});
  s.controlled.push_back({{3}, {{0.0, 1.0}, {Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 0.5)}}});
  s.updateConstraints();
  EXPECT_EQ(s.constrainedDofs, (std::vector<int>{0, 1, 2, 5, 9, 10, 11}));
  Eigen::VectorXd x = Eigen::VectorXd::Constant(12, 7.0), v = Eigen::VectorXd::Constant(12, 7.0);
  s.prescribe(0.5, x, v);
  EXPECT_DOUBLE_EQ(x[0], 0.0);
  EXPECT_DOUBLE_EQ(x[3], 7.0);   // node 1 free in x
  EXPECT_DOUBLE_EQ(x[5], 0.0);   // node 1 fixed in z
  EXPECT_DOUBLE_EQ(x[11], 1.25); // controlled node 3: rest z 1 + 0.25
  EXPECT_DOUBLE_EQ(v[11], 0.5);
}

TEST(SparsePattern, TetBlockLandsOnItsNodePairs) {
  Mesh m = unitTet();
  SparsePattern p(4, m.tets);
  SparseMatrix K = p.zeroMatrix();
  EXPECT_EQ(K.nonZeros(), 144);
  Matrix12d Ke;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) Ke(i, j) = 100 * i + j;
  p.addTetBlock(K, 0, Ke);
  Eigen::MatrixXd dense = K;
  EXPECT_EQ((dense - Eigen::MatrixXd(Ke)).norm(), 0.0);
}

}  // namespace
}  // namespace tt
