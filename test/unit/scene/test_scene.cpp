// What a scene builds: exactly what it lists, with the units, regions and boundary
// conditions it states.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <filesystem>
#include <fstream>

#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/scene/scene_runner.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

Scene sceneFrom(const std::string& text) {
  const fs::path path = fs::temp_directory_path() / "tt_scene_build.yaml";
  std::ofstream(path) << text;
  return loadScene(path.string());
}

const char* const kMinimal = R"(
mesh: {generator: box, nodes: [3, 3, 3], size: [20, 20, 40], length_unit: mm}
materials: [{young_modulus: 5000, poisson_ratio: 0.3, density: 1000}]
force_models: [{type: tensor_mass}]
integrator: {type: backward_euler}
)";

TEST(Scene, BuildsOnlyWhatItLists) {
  Scene scene = sceneFrom(kMinimal);
  const System& s = scene.system;
  ASSERT_EQ(s.models.size(), 1u);
  EXPECT_STREQ(s.models[0]->name(), "tensor_mass");
  EXPECT_EQ(s.damping.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(s.constrainedDofs.empty());
  EXPECT_TRUE(s.controlled.empty());
  EXPECT_EQ(scene.output.vtuEvery, 0);
  EXPECT_FALSE(scene.output.csv);

  // Without an output section nothing is written, even with an output folder.
  const fs::path out = fs::temp_directory_path() / "tt_scene_no_output";
  fs::remove_all(out);
  const RunSummary summary = runScene(scene, {0.02, out.string(), nullptr});
  EXPECT_EQ(summary.frames, 2);
  EXPECT_TRUE(summary.files.empty());
  EXPECT_TRUE(!fs::exists(out) || fs::is_empty(out));
}

TEST(Scene, UnitsScaleTheMeshAndStresses) {
  Scene scene = sceneFrom(kMinimal);
  const Box box = boundingBox(scene.system.mesh.rest);
  EXPECT_NEAR(box.max.z(), 0.04, 1e-15);
  // Lumped masses add up to density x volume (0.02 x 0.02 x 0.04 m^3 of 1000 kg/m^3).
  EXPECT_NEAR(scene.system.mass.sum() / 3.0, 1000 * 0.02 * 0.02 * 0.04, 1e-12);

  std::string kpa = kMinimal;
  kpa.replace(kpa.find("young_modulus: 5000"), 19, "young_modulus: 5, stress_unit: kPa");
  EXPECT_DOUBLE_EQ(sceneFrom(kpa).system.materials[0].elastic->mu,
                   scene.system.materials[0].elastic->mu);
}

TEST(Scene, RegionsBoundaryAxesLoadsAndFibres) {
  const std::string text = std::string(kMinimal) + R"(
materials:
  - {young_modulus: 5000, poisson_ratio: 0.3}
  - {region: {box: {min: [-1, -1, 0.02], max: [1, 1, 1]}}, young_modulus: 20000,
     young_modulus_longitudinal: 150000, poisson_ratio: 0.4, density: 1100}
fibres: {direction: [0, 0, 2]}
boundary:
  fixed:
    - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, axes: z}
    - {nodes: [0]}
  controlled:
    - {box: {min: [-1, -1, 0.039], max: [1, 1, 1]}, path: [[0, 0, 0, 0], [1, 0, 0, 0.01]]}
loads: {gravity: [0, 0, -9.81], rayleigh_mass: 2, node_damping: 0.5}
)";
  // The second 'materials' key overrides the first in this YAML text: remove the first.
  std::string scene = text;
  scene.erase(scene.find("materials: [{"), scene.find("force_models") - scene.find("materials: [{"));
  Scene sc = sceneFrom(scene);
  const System& s = sc.system;
  int upper = 0;
  for (int e = 0; e < s.mesh.numTets(); ++e) upper += s.mesh.material[e] == 1;
  EXPECT_GT(upper, 0);
  EXPECT_LT(upper, s.mesh.numTets());
  EXPECT_GT(s.materials[1].elastic->muL, s.materials[1].elastic->mu);
  EXPECT_TRUE(s.mesh.fibreFrame[0].col(0).isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(s.mesh.fibreFrame[0].determinant(), 1.0, 1e-12);
  // Bottom plane: z only (9 nodes), node 0: all axes, top layer controlled (9 nodes).
  EXPECT_EQ(s.constrainedDofs.size(), 9u + 2u + 27u);
  ASSERT_EQ(s.models.size(), 2u);
  EXPECT_STREQ(s.models[1]->name(), "gravity");
  EXPECT_NEAR(s.damping[5], 2.0 * s.mass[5] + 0.5, 1e-15);
  EXPECT_NEAR(s.controlled[0].path.offsetAt(0.5).z(), 0.005, 1e-15);
}

}  // namespace
}  // namespace tt
