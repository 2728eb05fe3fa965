// Scene keys of the simulation work: mesh.translate / mesh.rotate_deg (after units and
// scale, fibres turned along), contact (built only when listed), render_surface (an OBJ
// embedded in the tets), and what the node shows and reports: the display surface and strain.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>

#include "tissue_trainer/core/model/strain.h"
#include "tissue_trainer/core/scene/display_surface.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

Scene sceneFrom(const std::string& text, const std::string& name = "tt_scene_contact.yaml") {
  const fs::path path = fs::temp_directory_path() / name;
  std::ofstream(path) << text;
  return loadScene(path.string());
}

const char* const kBlock = R"(
mesh: {generator: box, nodes: [3, 3, 3], size: [20, 20, 40], length_unit: mm%s}
materials: [{young_modulus: 5000, poisson_ratio: 0.3}]
force_models: [{type: edge_length}]
integrator: {type: backward_euler}
)";

std::string block(const std::string& extra) {
  std::string text = kBlock;
  text.replace(text.find("%s"), 2, extra);
  return text;
}

TEST(SceneContact, TranslateAndRotateApplyAfterUnitsAndScale) {
  const Scene plain = sceneFrom(block(""));
  const Scene placed = sceneFrom(block(", scale: 2, rotate_deg: [0, 90, 0], translate: [1, 2, 3]"));
  // x_world = Ry(90) (2 x_mm / 1000) + t: the box's z extent (80 mm) now runs along +x.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (int a = 0; a < plain.system.numNodes(); ++a) {
    const Eigen::Vector3d expected = R * (2.0 * plain.system.mesh.rest.col(a)) + Eigen::Vector3d(1, 2, 3);
    EXPECT_LT((placed.system.mesh.rest.col(a) - expected).norm(), 1e-12);
  }
  const Box box = boundingBox(placed.system.mesh.rest);
  EXPECT_NEAR(box.max.x() - box.min.x(), 0.08, 1e-12);
  // Same masses (rotation keeps volumes and orientation), fibres turned with the mesh.
  EXPECT_NEAR(placed.system.mass.sum(), 8.0 * plain.system.mass.sum(), 1e-12);
  EXPECT_LT((placed.system.mesh.fibreFrame[0] - R * plain.system.mesh.fibreFrame[0]).norm(), 1e-12);
}

TEST(SceneContact, SpindleLiesAlongXWithTheBellyWhereTheSceneSaysSo) {
  const Scene s = sceneFrom(std::string(R"(
mesh: {generator: spindle, rotate_deg: [0, 90, 0], translate: [-0.085, 0.075, 0.04]}
materials: [{young_modulus: 20, poisson_ratio: 0.4, young_modulus_longitudinal: 150,
             poisson_ratio_longitudinal: 0.4, stress_unit: kPa}]
force_models: [{type: edge_length}]
integrator: {type: backward_euler}
)"));
  const Box box = boundingBox(s.system.mesh.rest);
  EXPECT_NEAR(box.min.x(), -0.085, 1e-9);
  EXPECT_NEAR(box.max.x(), 0.015, 1e-9);
  EXPECT_NEAR(0.5 * (box.min.y() + box.max.y()), 0.075, 1e-3);
  EXPECT_NEAR(0.5 * (box.min.z() + box.max.z()), 0.04, 1e-3);
  // Fibres along world x in the belly.
  double along = 0.0;
  for (const Eigen::Matrix3d& f : s.system.mesh.fibreFrame) along += std::abs(f(0, 0));
  EXPECT_GT(along / s.system.mesh.numTets(), 0.9);
  EXPECT_FALSE(s.system.constrainedDofs.empty());  // the tendon ends stay fixed
}

TEST(SceneContact, ContactIsBuiltOnlyWhenListed) {
  EXPECT_FALSE(sceneFrom(block("")).contact.has_value());
  const Scene defaults = sceneFrom(block("") + "contact:\n");
  ASSERT_TRUE(defaults.contact.has_value());
  EXPECT_EQ(defaults.contact->stiffness, ContactSettings{}.stiffness);
  const Scene listed = sceneFrom(block("") +
      "contact: {stiffness: 400, damping: 0.2, grasp_stiffness: 90, grasp_jaw_angle: 0.2,"
      " grasp_radius: 0.004, grasp_max_nodes: 5}\n");
  ASSERT_TRUE(listed.contact.has_value());
  EXPECT_EQ(listed.contact->stiffness, 400.0);
  EXPECT_EQ(listed.contact->damping, 0.2);
  EXPECT_EQ(listed.contact->graspStiffness, 90.0);
  EXPECT_EQ(listed.contact->graspJawAngle, 0.2);
  EXPECT_EQ(listed.contact->graspRadius, 0.004);
  EXPECT_EQ(listed.contact->graspMaxNodes, 5);
  EXPECT_EQ(listed.system.models.size(), 1u);  // the contact model comes with the contact library
  EXPECT_EQ(listed.contact->stiffnessPerArea, 0.0);
  EXPECT_EQ(listed.contact->sampleSpacing, 0.0);
  const Scene perArea = sceneFrom(block("") + "contact: {stiffness_per_area: 2.5e6, sample_spacing: 5e-4}\n");
  ASSERT_TRUE(perArea.contact.has_value());
  EXPECT_EQ(perArea.contact->stiffnessPerArea, 2.5e6);
  EXPECT_EQ(perArea.contact->sampleSpacing, 5e-4);
  EXPECT_EQ(perArea.contact->toolMaxSpeed, ContactSettings{}.toolMaxSpeed);
  EXPECT_EQ(sceneFrom(block("") + "contact: {tool_max_speed: 0.25}\n").contact->toolMaxSpeed, 0.25);
}

TEST(SceneContact, TheLongestFrameIsReadOnlyWhenListed) {
  EXPECT_FALSE(sceneFrom(block("")).maxFrameTime.has_value());
  const Scene listed = sceneFrom(block("") + "run: {frame_time: 0.02, max_frame_time: 0.08}\n");
  ASSERT_TRUE(listed.maxFrameTime.has_value());
  EXPECT_EQ(*listed.maxFrameTime, 0.08);
  EXPECT_EQ(*sceneFrom(block("") + "run: {frame_time: 0.02, max_frame_time: 0.02}\n").maxFrameTime, 0.02);
}

TEST(SceneContact, RenderSurfaceIsEmbeddedAndShown) {
  // An OBJ in the mesh file's units (mm): one triangle inside the block, one corner outside.
  const fs::path obj = fs::temp_directory_path() / "tt_render_surface.obj";
  std::ofstream(obj) << "v 5 5 5\nv 15 5 5\nv 5 15 21\nv 10 10 41\nf 1 2 3\nf 1 2 4\n";
  const Scene s = sceneFrom(block(", translate: [0.1, 0, 0]") +
                            "render_surface: {file: " + obj.string() + "}\n");
  ASSERT_TRUE(s.renderSurface.has_value());
  EXPECT_EQ(s.renderSurface->triangles.size(), 2u);
  EXPECT_LT((s.renderSurface->rest.col(1) - Eigen::Vector3d(0.115, 0.005, 0.005)).norm(), 1e-12);
  EXPECT_EQ(s.renderSurface->embedding.numOutside(), 1);
  const DisplaySurface display(s);
  EXPECT_TRUE(display.embedded());
  EXPECT_EQ(display.numVertices(), 4);
  // A rigid translation of the tets moves the embedded vertices with them.
  Eigen::VectorXd x = s.system.state.x;
  for (int a = 0; a < s.system.numNodes(); ++a) x[3 * a + 1] += 0.01;
  Eigen::Matrix3Xd p;
  display.positions(x, p);
  EXPECT_LT((p - (s.renderSurface->rest.colwise() + Eigen::Vector3d(0, 0.01, 0))).norm(), 1e-12);

  // Without a render surface: the boundary triangles over the nodes they use.
  const Scene plain = sceneFrom(block(""));
  const DisplaySurface boundary(plain);
  EXPECT_FALSE(boundary.embedded());
  EXPECT_EQ(boundary.triangles().size(), plain.system.mesh.surface.size());
  EXPECT_EQ(boundary.numVertices(), 26);  // all 27 nodes but the centre
  boundary.positions(plain.system.state.x, p);
  for (size_t t = 0; t < plain.system.mesh.surface.size(); ++t)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(p.col(boundary.triangles()[t][k]),
                plain.system.mesh.rest.col(plain.system.mesh.surface[t][k]));
}

TEST(SceneContact, StrainOfAUniformStretch) {
  const Scene s = sceneFrom(block(""));
  const StrainSummary rest = measureStrain(s.system.mesh, s.system.state.x, 0.1);
  EXPECT_LT(rest.maxStrain, 1e-12);
  EXPECT_EQ(rest.strainedVolume, 0.0);
  // 10 % along x: E_xx = (1.1^2 - 1) / 2 = 0.105, the only non-zero entry.
  Eigen::VectorXd x = s.system.state.x;
  for (int a = 0; a < s.system.numNodes(); ++a) x[3 * a] *= 1.1;
  const StrainSummary stretched = measureStrain(s.system.mesh, x, 0.1);
  EXPECT_NEAR(stretched.maxStrain, 0.105, 1e-12);
  EXPECT_NEAR(stretched.strainedVolume, 0.02 * 0.02 * 0.04, 1e-15);
  EXPECT_EQ(stretched.strainedTets, s.system.mesh.numTets());
  EXPECT_EQ(measureStrain(s.system.mesh, x, 0.2).strainedVolume, 0.0);
}

}  // namespace
}  // namespace tt
