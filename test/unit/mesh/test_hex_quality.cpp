// The quality report checks a hex through the six tets of its split: a hex twisted so that
// one corner is pushed inside is inverted even though its total volume stays positive.
#include <gtest/gtest.h>

#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/mesh/quality.h"

namespace tt {
namespace {

TEST(HexQuality, ACornerPushedInsideIsInvertedThoughTheVolumeIsPositive) {
  Mesh cube = boxGrid(2, 2, 2, Eigen::Vector3d::Ones(), TetSplit::kNone);
  EXPECT_EQ(meshQuality(cube).inverted, 0);
  EXPECT_EQ(meshQuality(cube).degenerate, 0);
  // Node 1, the corner (1, 0, 0), pushed deep inside: its tets of the split turn over.
  cube.rest.col(cube.hexes[0][1]) = Eigen::Vector3d(0.1, 0.5, 0.5);
  ASSERT_GT(hexVolume(cube.rest, cube.hexes[0]), 0.0);
  EXPECT_EQ(meshQuality(cube).inverted + meshQuality(cube).degenerate, 1);
}

}  // namespace
}  // namespace tt
