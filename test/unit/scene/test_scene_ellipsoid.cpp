// The truncated_ellipsoid mesh generator of a scene (the left ventricle of Land et al.,
// "Verification of cardiac mechanics software", Sec. 2c(ii)) and its `ellipsoid` fibres: the
// defaults are the paper's geometry in any length_unit, the cells and the split as given, the
// base fixed, the placement applied, and the fibre frames those of the unplaced wall turned
// with the mesh.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "scene_test_util.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

using testutil::replaced;
using testutil::writeScene;

const char* const kVentricleScene = R"(mesh:
  generator: truncated_ellipsoid
MESH
fibres: {ellipsoid: {angles_deg: [60, -60]}}
materials: [{young_modulus: 3000, poisson_ratio: 0.3}]
force_models: [{type: hyperelastic, law: neo_hookean}]
integrator: {type: explicit_euler, time_step: 1.0e-5}
)";

Mesh loadVentricle(const std::string& name, const std::string& meshKeys) {
  return loadScene(writeScene(name, replaced(kVentricleScene, "MESH\n", meshKeys))).system.mesh;
}

int fixedNodeCount(const Mesh& m) {
  int fixed = 0;
  for (std::uint8_t tag : m.nodeTags) fixed += tag == kFixedAll;
  return fixed;
}

TEST(EllipsoidScene, DefaultsAreLandsVentricleInAnyLengthUnit) {
  const Mesh metres = loadVentricle("ventricle_m.yaml", "");
  // 2 x 8 x 16 cells split into six tets, three in each apex cell.
  EXPECT_EQ(metres.numNodes(), 3 * (1 + 8 * 16));
  EXPECT_EQ(metres.numTets(), 6 * (2 * 7 * 16) + 3 * (2 * 16));
  EXPECT_EQ(metres.numHexes(), 0);
  EXPECT_EQ(fixedNodeCount(metres), 3 * 16);
  EXPECT_NEAR(metres.rest.row(2).minCoeff(), -0.020, 1e-15);
  EXPECT_NEAR(metres.rest.row(2).maxCoeff(), 0.005, 1e-15);
  EXPECT_NEAR(metres.rest.row(0).maxCoeff(), 0.010, 1e-5);  // the epicardium's short radius
  const Mesh millimetres = loadVentricle("ventricle_mm.yaml", "  length_unit: mm\n");
  ASSERT_EQ(millimetres.numNodes(), metres.numNodes());
  EXPECT_TRUE(millimetres.rest.isApprox(metres.rest, 1e-12));
}

TEST(EllipsoidScene, CellsRadiiCutSplitAndPlacement) {
  const Mesh m = loadVentricle("ventricle_keys.yaml",
                           "  cells_transmural: 1\n  cells_meridional: 3\n  cells_circumferential: 5\n"
                           "  endocardium: [20, 40]\n  epicardium: [30, 50]\n  base_z: 10\n"
                           "  split: none\n  length_unit: mm\n  scale: 2\n"
                           "  rotate_deg: [0, 90, 0]\n  translate: [0.1, 0.2, 0.3]\n");
  EXPECT_EQ(m.numNodes(), 2 * (1 + 3 * 5));
  EXPECT_EQ(m.numHexes(), 15);
  EXPECT_EQ(m.numTets(), 0);
  EXPECT_EQ(fixedNodeCount(m), 2 * 5);
  // Rotated 90 degrees about y: the long axis z goes to x. Apexes at z = -0.04 and -0.05 m
  // (scale 2: -0.08, -0.10) land on x = -0.08, -0.10, then are translated.
  const Eigen::Vector3d shift(0.1, 0.2, 0.3);
  EXPECT_TRUE(m.rest.col(ellipsoidNode(EllipsoidShape{}, 0, 0, 0)).isApprox(shift + Eigen::Vector3d(-0.08, 0, 0), 1e-12));
  EXPECT_TRUE(m.rest.col(1).isApprox(shift + Eigen::Vector3d(-0.10, 0, 0), 1e-12));
  for (int n = 0; n < m.numNodes(); ++n)
    EXPECT_EQ(m.nodeTags[n] == kFixedAll, std::abs(m.rest(0, n) - (0.1 + 0.02)) < 1e-12) << n;
}

// The frames of a placed ventricle are those of the unplaced one turned by rotate_deg: the
// wall coordinates are taken in the generator's own coordinates.
TEST(EllipsoidScene, FibresAreTakenBeforePlacementAndTurnWithTheMesh) {
  const Mesh own = loadVentricle("ventricle_own.yaml", "  length_unit: mm\n");
  const Mesh placed = loadVentricle("ventricle_placed.yaml",
                               "  length_unit: mm\n  scale: 2.5\n  rotate_deg: [20, -78, 35]\n"
                               "  translate: [-0.035, 0.08, 0.03]\n");
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(35 * M_PI / 180, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(-78 * M_PI / 180, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(20 * M_PI / 180, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  ASSERT_EQ(own.numTets(), placed.numTets());
  for (int e = 0; e < own.numTets(); ++e) {
    const Eigen::Matrix3d& B = placed.fibreFrame[e];
    EXPECT_TRUE((B.transpose() * B).isIdentity(1e-12));
    EXPECT_TRUE(B.isApprox(R * own.fibreFrame[e], 1e-12)) << "tet " << e;
  }
}

// The unplaced wall: tets of the inner layer (all nodes in layers 0 and 1 of 2) have fibre
// angles between +60 and 0 degrees, those of the outer layer between 0 and -60, measured from
// the circumferential direction (-y, x, 0) towards the base about the sheet (the wall normal).
// A centroid may lie just inside the endocardium or outside the epicardium (the faces are
// chords of the spheroids), where the angle is held at the face's.
TEST(EllipsoidScene, FibreAnglesOfTheInnerAndOuterLayers) {
  const EllipsoidShape shape;
  const Mesh m = loadVentricle("ventricle_layers.yaml", "");
  const auto layerOf = [&](int node) {
    if (node <= shape.transmural) return node;
    return (node - (shape.transmural + 1)) / (shape.meridional * shape.circumferential);
  };
  int inner = 0, outer = 0;
  double innerMean = 0.0, outerMean = 0.0;
  for (int e = 0; e < m.numTets(); ++e) {
    int lowest = 2, highest = 0;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int a : m.tets[e]) {
      lowest = std::min(lowest, layerOf(a));
      highest = std::max(highest, layerOf(a));
      c += 0.25 * m.rest.col(a);
    }
    const Eigen::Matrix3d& B = m.fibreFrame[e];
    const Eigen::Vector3d around = Eigen::Vector3d(-c.y(), c.x(), 0.0).normalized();
    const Eigen::Vector3d towardsBase = B.col(1).cross(around);
    const double angle = std::atan2(B.col(0).dot(towardsBase), B.col(0).dot(around)) * 180 / M_PI;
    EXPECT_NEAR(B.col(1).dot(around), 0.0, 1e-12) << "tet " << e;
    EXPECT_GT(towardsBase.z(), 0.0) << "tet " << e;
    if (highest <= 1) {
      ++inner;
      innerMean += angle;
      EXPECT_GE(angle, -1e-9) << "tet " << e;
      EXPECT_LE(angle, 60.0 + 1e-9) << "tet " << e;
    } else if (lowest >= 1) {
      ++outer;
      outerMean += angle;
      EXPECT_LE(angle, 1e-9) << "tet " << e;
      EXPECT_GE(angle, -60.0 - 1e-9) << "tet " << e;
    }
  }
  ASSERT_EQ(inner, m.numTets() / 2);
  ASSERT_EQ(outer, m.numTets() / 2);
  std::printf("[ measured ] mean fibre angle %.2f degrees in the inner layer, %.2f in the outer\n",
              innerMean / inner, outerMean / outer);
  EXPECT_GT(innerMean / inner, 20.0);
  EXPECT_LT(outerMean / outer, -20.0);
}

}  // namespace
}  // namespace tt
