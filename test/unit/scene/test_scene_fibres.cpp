// Fibre frames beyond one global frame ("Adamss: Advanced Anisotropic Mass-Spring System",
// Secs. 2.3 and 2.8.1): a frame per material region, a per-element field read from a file and
// a transmural rotation of the fibre about the wall normal.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <string>

#include "scene_test_util.h"
#include "tissue_trainer/core/mesh/fibre_field.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

using testutil::replaced;
using testutil::writeScene;

// 2 x 2 x 2 cells of 6 tets each (48 tets), 1 cm.
const char* const kFibreFieldScene = R"(mesh: {generator: box, nodes: [3, 3, 3], size: [0.01, 0.01, 0.01], split: six}
FIBRES
materials:
  - young_modulus: 3000
    poisson_ratio: 0.3
  - region: {box: {min: [-1, -1, 0.005], max: [1, 1, 1]}}
    young_modulus: 3000
    poisson_ratio: 0.3
force_models: [{type: edge_length}]
integrator: {type: explicit_euler, time_step: 1.0e-5}
)";

Eigen::Vector3d tetCentroid(const Mesh& mesh, int e) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int a : mesh.tets[e]) c += 0.25 * mesh.rest.col(a);
  return c;
}

void expectOrthonormalRightHanded(const Eigen::Matrix3d& B) {
  EXPECT_TRUE((B.transpose() * B).isIdentity(1e-12)) << B;
  EXPECT_NEAR(B.determinant(), 1.0, 1e-12);
}

TEST(FibreScene, EachMaterialRegionHasItsOwnFrame) {
  std::string text = replaced(kFibreFieldScene, "FIBRES", "fibres: {direction: [1, 0, 0]}");
  text = replaced(text, "    young_modulus: 3000\n    poisson_ratio: 0.3\nforce",
                  "    young_modulus: 3000\n    poisson_ratio: 0.3\n"
                  "    fibres: {direction: [0, 1, 0], sheet: [0, 0, 1]}\nforce");
  const Mesh& mesh = loadScene(writeScene("region_fibres.yaml", text)).system.mesh;
  ASSERT_EQ(mesh.numTets(), 48);
  int upper = 0;
  for (int e = 0; e < mesh.numTets(); ++e) {
    const bool inUpper = tetCentroid(mesh, e).z() >= 0.005;
    upper += inUpper;
    EXPECT_EQ(mesh.material[e], inUpper ? 1 : 0);
    const Eigen::Matrix3d& B = mesh.fibreFrame[e];
    expectOrthonormalRightHanded(B);
    // The upper region: the material's frame; the lower one: the top-level frame.
    if (inUpper) {
      EXPECT_TRUE(B.isApprox((Eigen::Matrix3d() << 0, 0, 1, 1, 0, 0, 0, 1, 0).finished(), 1e-15))
          << "tet " << e << "\n" << B;
    } else {
      EXPECT_TRUE(B.col(0).isApprox(Eigen::Vector3d::UnitX(), 1e-15)) << "tet " << e;
    }
  }
  EXPECT_EQ(upper, 24);
}

TEST(FibreScene, FileFramesReadBackPerElement) {
  // Even rows: angles (phi = e degrees, theta = 90 - e); odd rows: fibre and sheet vectors of
  // any length, the sheet not orthogonal (its fibre part is removed).
  const std::string path = writeScene("frames.txt", [] {
    std::string rows = "# fibre frames, one row per tet\n";
    for (int e = 0; e < 48; ++e) {
      if (e % 2 == 0)
        rows += std::to_string(e) + " " + std::to_string(90 - e) + "\n";
      else
        rows += "\n  2 0 " + std::to_string(0.1 * e) + "   1 3 0  # tet " + std::to_string(e) + "\n";
    }
    return rows;
  }());
  for (const bool rotated : {false, true}) {
    std::string text = replaced(kFibreFieldScene, "FIBRES", "fibres: {file: frames.txt}");
    if (rotated) text = replaced(text, "split: six}", "split: six, rotate_deg: [0, 0, 90]}");
    const Mesh& mesh = loadScene(writeScene("file_fibres.yaml", text)).system.mesh;
    const Eigen::Matrix3d R =
        rotated ? Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix()
                : Eigen::Matrix3d::Identity();
    ASSERT_EQ(mesh.numTets(), 48);
    for (int e = 0; e < 48; ++e) {
      const Eigen::Matrix3d& B = mesh.fibreFrame[e];
      expectOrthonormalRightHanded(B);
      if (e % 2 == 0) {
        const double p = e * M_PI / 180, t = (90 - e) * M_PI / 180;
        const Eigen::Vector3d fibre(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
        const Eigen::Vector3d sheet(std::cos(t) * std::cos(p), std::cos(t) * std::sin(p), -std::sin(t));
        EXPECT_TRUE(B.col(0).isApprox(R * fibre, 1e-12)) << "tet " << e;
        EXPECT_TRUE(B.col(1).isApprox(R * sheet, 1e-12)) << "tet " << e;
      } else {
        const Eigen::Vector3d fibre = Eigen::Vector3d(2, 0, 0.1 * e).normalized();
        Eigen::Vector3d sheet = Eigen::Vector3d(1, 3, 0);
        sheet = (sheet - sheet.dot(fibre) * fibre).normalized();
        EXPECT_TRUE(B.col(0).isApprox(R * fibre, 1e-12)) << "tet " << e;
        EXPECT_TRUE(B.col(1).isApprox(R * sheet, 1e-12)) << "tet " << e;
      }
    }
  }
}

// The fibre of every element turns from +60 to -60 degrees about the wall normal z over the
// mesh's thickness, measured at the element's centroid; the sheet is the normal.
TEST(FibreScene, TransmuralAngleFollowsTheCentroidDepth) {
  const std::string text = replaced(
      kFibreFieldScene, "FIBRES",
      "fibres: {transmural: {normal: [0, 0, 2], direction: [1, 0, 0.5], angles_deg: [60, -60]}}");
  const Mesh& mesh = loadScene(writeScene("transmural.yaml", text)).system.mesh;
  for (int e = 0; e < mesh.numTets(); ++e) {
    const Eigen::Matrix3d& B = mesh.fibreFrame[e];
    expectOrthonormalRightHanded(B);
    const double depth = tetCentroid(mesh, e).z() / 0.01;
    const double angle = (60.0 - 120.0 * depth) * M_PI / 180.0;
    EXPECT_NEAR(std::atan2(B(1, 0), B(0, 0)), angle, 1e-12) << "tet " << e;
    EXPECT_NEAR(B(2, 0), 0.0, 1e-15);
    EXPECT_TRUE(B.col(1).isApprox(Eigen::Vector3d::UnitZ(), 1e-15));
  }
}

// A region of its own: the wall is the region's extent (given here), the other region keeps
// the file-less default, the identity frame.
TEST(FibreScene, TransmuralPerRegionWithExtent) {
  std::string text = replaced(kFibreFieldScene, "FIBRES\n", "");
  text = replaced(text, "    young_modulus: 3000\n    poisson_ratio: 0.3\nforce",
                  "    young_modulus: 3000\n    poisson_ratio: 0.3\n"
                  "    fibres:\n      transmural: {normal: [0, 0, 1], direction: [1, 0, 0],\n"
                  "                   angles_deg: [60, -60], extent: [0.005, 0.01]}\nforce");
  const Mesh& mesh = loadScene(writeScene("transmural_region.yaml", text)).system.mesh;
  for (int e = 0; e < mesh.numTets(); ++e) {
    const Eigen::Vector3d c = tetCentroid(mesh, e);
    if (c.z() < 0.005) {
      EXPECT_TRUE(mesh.fibreFrame[e].isIdentity(0.0)) << "tet " << e;
      continue;
    }
    const double angle = (60.0 - 120.0 * (c.z() - 0.005) / 0.005) * M_PI / 180.0;
    EXPECT_NEAR(std::atan2(mesh.fibreFrame[e](1, 0), mesh.fibreFrame[e](0, 0)), angle, 1e-12);
  }
}

TEST(TransmuralFibres, AngleAtTheTwoFacesAndInTheMiddle) {
  TransmuralFibres t;
  t.normal = Eigen::Vector3d(1, 2, 2) / 3.0;
  t.reference = Eigen::Vector3d(2, -1, 0).normalized();
  t.from = -0.01;
  t.to = 0.02;
  t.angleFrom = 60 * M_PI / 180;
  t.angleTo = -60 * M_PI / 180;
  const Eigen::Vector3d inPlane = Eigen::Vector3d(0.3, 0.7, -0.1);  // any in-plane offset
  const auto at = [&](double s) {
    return Eigen::Vector3d(s * t.normal + inPlane - inPlane.dot(t.normal) * t.normal);
  };
  const Eigen::Vector3d side = t.normal.cross(t.reference);
  const struct { double s, degrees; } cases[] = {
      {-0.01, 60}, {0.02, -60}, {0.005, 0}, {0.0125, -30}, {-0.5, 60}, {0.5, -60}};
  for (const auto& c : cases) {
    EXPECT_NEAR(t.angleAt(at(c.s)), c.degrees * M_PI / 180, 1e-14) << c.s;
    const Eigen::Matrix3d B = t.frameAt(at(c.s));
    expectOrthonormalRightHanded(B);
    // The fibre lies in the wall plane at the angle from the reference, turned about the normal.
    EXPECT_NEAR(B.col(0).dot(t.normal), 0.0, 1e-15);
    EXPECT_NEAR(std::atan2(B.col(0).dot(side), B.col(0).dot(t.reference)), c.degrees * M_PI / 180,
                1e-14);
    EXPECT_TRUE(B.col(1).isApprox(t.normal, 1e-15));
  }
}

TEST(FibreFrames, VectorsAndAngles) {
  Eigen::Matrix3d B;
  ASSERT_EQ(fibreFrameFromVectors({0, 0, 3}, {1, 0, 1}, B), FrameProblem::kNone);
  EXPECT_TRUE(B.isApprox((Eigen::Matrix3d() << 0, 1, 0, 0, 0, 1, 1, 0, 0).finished(), 1e-15)) << B;
  EXPECT_EQ(fibreFrameFromVectors({0, 0, 0}, {1, 0, 0}, B), FrameProblem::kZeroFibre);
  EXPECT_EQ(fibreFrameFromVectors({1, 0, 0}, {0, 0, 0}, B), FrameProblem::kZeroSheet);
  EXPECT_EQ(fibreFrameFromVectors({1, 0, 0}, {-2, 1e-9, 0}, B), FrameProblem::kParallel);
  // theta = 90: the fibre in the x-y plane at phi, the sheet along -z.
  B = fibreFrameFromAngles(30, 90);
  EXPECT_TRUE(B.col(0).isApprox(Eigen::Vector3d(std::sqrt(3) / 2, 0.5, 0), 1e-15));
  EXPECT_NEAR((B.col(1) - Eigen::Vector3d(0, 0, -1)).norm(), 0.0, 1e-15);
  expectOrthonormalRightHanded(B);
}

}  // namespace
}  // namespace tt
