// Corrupt elements ("Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.9.1): a tet whose
// signed volume changed sign or went flat, a hex that is no longer a simple polyhedron (found
// through its tet splits), hex face areas and normals averaged over the two triangulations of a
// face, and the hex volume from its tets.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "tissue_trainer/core/element/hex8.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/mesh/corrupt_elements.h"
#include "tissue_trainer/core/mesh/quality.h"

namespace tt {
namespace {

Mesh unitHex() { return boxGrid(2, 2, 2, Eigen::Vector3d::Ones(), TetSplit::kNone); }

TEST(CorruptElements, HexWithANodePushedThroughTheOppositeFaceIsFound) {
  // Fig. 2.30: node 5 (1, 0, 1) moved across the face x = 0 (nodes 0, 3, 7, 4).
  const Mesh mesh = unitHex();
  ASSERT_EQ(mesh.numHexes(), 1);
  const int node5 = mesh.hexes[0][5];
  Eigen::Matrix3Xd x = mesh.rest;
  EXPECT_TRUE(corruptElements(mesh, x).empty());
  x.col(node5) = Eigen::Vector3d(-0.4, 0.1, 0.9);
  for (const HexSplit split : {HexSplit::kSix, HexSplit::kFive, HexSplit::kBoth}) {
    const std::vector<CorruptElement> found = corruptElements(mesh, x, 0.01, split);
    ASSERT_EQ(found.size(), 1u);
    EXPECT_TRUE(found[0].hex);
    EXPECT_EQ(found[0].index, 0);
    EXPECT_EQ(found[0].reason, CorruptReason::kInverted);
    EXPECT_LT(found[0].volumeRatio, 0.0);
    if (split == HexSplit::kSix) EXPECT_LT(found[0].subTet, 6);
    if (split == HexSplit::kFive) EXPECT_GE(found[0].subTet, 6);
  }
  EXPECT_NE(describeCorrupt(corruptElements(mesh, x)[0]).find("hex 0 not a simple polyhedron: tet "),
            std::string::npos);
}

TEST(CorruptElements, MildlyDistortedNonPlanarHexIsNot) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.12, 0.12);
  const Mesh mesh = unitHex();
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Matrix3Xd x = mesh.rest;
    for (int n = 0; n < x.cols(); ++n)
      for (int k = 0; k < 3; ++k) x(k, n) += jitter(rng);
    // The faces are no longer planar, the hex is still simple.
    const FaceArea top = hexFaceArea(x, mesh.hexes[0], 1);
    EXPECT_TRUE(corruptElements(mesh, x).empty()) << "trial " << trial;
    EXPECT_GT(top.area, 0.0);
  }
  // The top face twisted by 20 degrees about the hex's axis: non-planar side faces.
  Eigen::Matrix3Xd x = mesh.rest;
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(20 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (int n = 4; n < 8; ++n) {
    const int node = mesh.hexes[0][n];
    x.col(node) = turn * (x.col(node) - Eigen::Vector3d(0.5, 0.5, 0)) + Eigen::Vector3d(0.5, 0.5, 0);
  }
  EXPECT_TRUE(corruptElements(mesh, x).empty());
}

TEST(CorruptElements, TetInvertedOrFlat) {
  Mesh mesh;
  mesh.rest.resize(3, 4);
  mesh.rest << 0, 1, 0, 0,  //
      0, 0, 1, 0,           //
      0, 0, 0, 1;
  mesh.tets = {{0, 1, 2, 3}};
  mesh.fillDefaults();
  Eigen::Matrix3Xd x = mesh.rest;
  EXPECT_TRUE(corruptElements(mesh, x).empty());
  x(2, 3) = 0.02;  // 2 % of the rest volume: healthy at the default limit of 1 %
  EXPECT_TRUE(corruptElements(mesh, x).empty());
  x(2, 3) = 0.005;
  std::vector<CorruptElement> found = corruptElements(mesh, x);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_FALSE(found[0].hex);
  EXPECT_EQ(found[0].reason, CorruptReason::kFlat);
  EXPECT_NEAR(found[0].volumeRatio, 0.005, 1e-15);
  x(2, 3) = -0.3;  // through the opposite face
  found = corruptElements(mesh, x);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].reason, CorruptReason::kInverted);
  EXPECT_NEAR(found[0].volumeRatio, -0.3, 1e-15);
  EXPECT_EQ(describeCorrupt(found[0]), "tet 0 inverted (volume -0.3 of rest)");
}

// A frustum (planar trapezoid side faces) under a random affine map: each face's mean area
// is the exact area of the planar quad and its normal the outward unit normal; the volume from
// either split is the exact volume.
TEST(HexFaces, FaceAverageAreasAreExactOnPlanarFaces) {
  Mesh mesh = unitHex();
  const Hex& h = mesh.hexes[0];
  for (int n = 4; n < 8; ++n)  // the top face shrunk to 0.6 about its centre
    mesh.rest.col(h[n]) = Eigen::Vector3d(0.5, 0.5, 1) + 0.6 * (mesh.rest.col(h[n]) - Eigen::Vector3d(0.5, 0.5, 1));
  Eigen::Matrix3d A;
  A << 1.3, 0.2, -0.1, 0.1, 0.8, 0.3, -0.2, 0.1, 1.1;
  ASSERT_GT(A.determinant(), 0.0);
  const Eigen::Matrix3Xd x = (A * mesh.rest).colwise() + Eigen::Vector3d(0.3, -0.2, 0.5);
  const Eigen::Vector3d centre = x.rowwise().mean();
  for (int f = 0; f < Hex8::kFaces; ++f) {
    const int* q = Hex8::faces[f];
    const Eigen::Vector3d a = x.col(h[q[0]]), b = x.col(h[q[1]]), c = x.col(h[q[2]]), d = x.col(h[q[3]]);
    // Planar quad: the exact area is half the cross product of the diagonals.
    const Eigen::Vector3d vectorArea = 0.5 * (c - a).cross(d - b);
    ASSERT_NEAR(vectorArea.normalized().dot(b - a), 0.0, 1e-12);  // planar indeed
    const FaceArea face = hexFaceArea(x, h, f);
    EXPECT_NEAR(face.area, vectorArea.norm(), 1e-14) << "face " << f;
    EXPECT_TRUE(face.normal.isApprox(vectorArea.normalized(), 1e-14)) << "face " << f;
    EXPECT_GT(face.normal.dot(0.25 * (a + b + c + d) - centre), 0.0) << "outward, face " << f;
  }
  const double exact = hexVolume(x, h);
  EXPECT_NEAR(exact, A.determinant() * (1 + 0.6 + 0.36) / 3, 1e-14);  // frustum volume
  EXPECT_NEAR(hexVolumeFromTets(x, h, true), exact, 1e-14);
  EXPECT_NEAR(hexVolumeFromTets(x, h, false), exact, 1e-14);
}

// On a non-planar face the two triangulations differ and the mean lies between them.
TEST(HexFaces, NonPlanarFaceAveragesItsTwoTriangulations) {
  Mesh mesh = unitHex();
  const Hex& h = mesh.hexes[0];
  Eigen::Matrix3Xd x = mesh.rest;
  x.col(h[6])(2) += 0.4;  // top face (4, 5, 6, 7): node 6 raised
  const auto area = [&](int i, int j, int k) {
    return 0.5 * (x.col(h[j]) - x.col(h[i])).cross(x.col(h[k]) - x.col(h[i])).norm();
  };
  const double alongAC = area(4, 5, 6) + area(4, 6, 7), alongBD = area(4, 5, 7) + area(5, 6, 7);
  ASSERT_GT(std::abs(alongAC - alongBD), 1e-3);
  EXPECT_NEAR(hexFaceArea(x, h, 1).area, 0.5 * (alongAC + alongBD), 1e-15);
  const Eigen::Vector3d n = hexFaceArea(x, h, 1).normal;
  EXPECT_NEAR(n.norm(), 1.0, 1e-15);
  EXPECT_GT(n.z(), 0.9);
}

}  // namespace
}  // namespace tt
