// Scenes over the generic element model: a hex-only mesh runs dynamically, a tet-only model
// refuses hexes, and a real mesh with slivers runs under the Neo-Hookean law with inversion
// handling where the edge_length StVK stops.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/mesh/mesh_order.h"
#include "tissue_trainer/core/mesh/quality.h"
#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/scene/scene_runner.h"

namespace tt {
namespace {

namespace fs = std::filesystem;
const fs::path kRoot = TT_SOURCE_DIR;

Scene sceneFrom(const std::string& text, const std::string& name) {
  const fs::path path = fs::temp_directory_path() / (name + ".yaml");
  std::ofstream(path) << text;
  return loadScene(path.string());
}

const char* const kHexBeam = R"(
mesh: {generator: box, nodes: [9, 3, 3], size: [80, 20, 20], length_unit: mm, split: none}
materials: [{young_modulus: 20, stress_unit: kPa, poisson_ratio: 0.4, density: 1000}]
force_models: [{type: hyperelastic, law: LAW}]
integrator: {type: backward_euler}
boundary: {fixed: [{box: {min: [-1, -1, -1], max: [0.001, 1, 1]}}]}
loads: {gravity: [0, 0, -9.81], rayleigh_mass: 5.0}
)";

std::string withLaw(const std::string& law) {
  return std::regex_replace(std::string(kHexBeam), std::regex("LAW"), law);
}

TEST(ElementScenes, HexOnlyBeamSagsUnderGravity) {
  for (const char* law : {"stvk", "neo_hookean"}) {
    Scene scene = sceneFrom(withLaw(law), "tt_hex_beam");
    const System& s = scene.system;
    ASSERT_EQ(s.mesh.numTets(), 0);
    ASSERT_EQ(s.mesh.numHexes(), 32);
    EXPECT_NEAR(s.mass.sum() / 3.0, 1000.0 * 0.08 * 0.02 * 0.02, 1e-12);  // rho V, lumped by 8
    const RunSummary run = runScene(scene, {0.5, "", nullptr});
    ASSERT_TRUE(run.ok) << law << ": " << run.failure;
    EXPECT_EQ(run.frames, 50);
    // The free end (x = 80 mm) has moved down; the clamped end has not moved.
    double tipDrop = 0.0, clampMove = 0.0;
    for (int n = 0; n < s.mesh.numNodes(); ++n) {
      const Eigen::Vector3d u = s.state.x.segment<3>(3 * n) - s.mesh.rest.col(n);
      if (s.mesh.rest(0, n) > 0.0799) tipDrop = std::max(tipDrop, -u.z());
      if (s.mesh.rest(0, n) < 0.0001) clampMove = std::max(clampMove, u.norm());
    }
    // Euler-Bernoulli gives a static tip deflection of 7.5 cm for this soft beam; in 0.5 s it
    // has fallen part of the way, and a hex model that blew up would be far outside.
    EXPECT_GT(tipDrop, 1e-2) << law;
    EXPECT_LT(tipDrop, 0.15) << law;
    EXPECT_EQ(clampMove, 0.0) << law;
  }
}

// The same beam read from a Gmsh file of hexahedra (type 5) runs the same as generated: in the
// file's order bit for bit, renumbered at load (mesh.node_order) up to the rounding the other
// summation order leaves in the linear solves (compared in the file's order).
TEST(ElementScenes, HexBeamFromAGmshFileRunsLikeTheGeneratedOne) {
  Scene generated = sceneFrom(withLaw("neo_hookean"), "tt_hex_beam_generated");
  const fs::path msh = fs::temp_directory_path() / "tt_hex_beam.msh";
  Mesh mesh = generated.system.mesh;
  writeMesh(msh.string(), mesh);
  const RunSummary a = runScene(generated, {0.1, "", nullptr});
  ASSERT_TRUE(a.ok) << a.failure;
  const Eigen::VectorXd u = generated.system.state.x - Eigen::Map<const Eigen::VectorXd>(
                                                           mesh.rest.data(), mesh.rest.size());
  for (const std::string order : {"file", "rcm"}) {
    std::string text = std::regex_replace(
        withLaw("neo_hookean"), std::regex(R"(\{generator: box[^}]*\})"),
        "{file: " + msh.string() + ", node_order: " + order + "}");
    Scene fromFile = sceneFrom(text, "tt_hex_beam_gmsh");
    ASSERT_EQ(fromFile.system.mesh.numHexes(), 32);
    ASSERT_EQ(fromFile.system.mesh.numTets(), 0);
    const RunSummary b = runScene(fromFile, {0.1, "", nullptr});
    ASSERT_TRUE(b.ok) << b.failure;
    const Eigen::VectorXd x = nodeValuesToFile(fromFile.system.mesh.numbering, fromFile.system.state.x);
    const double tolerance = order == "file" ? 1e-9 : 1e-5 * u.lpNorm<Eigen::Infinity>();
    EXPECT_LT((generated.system.state.x - x).lpNorm<Eigen::Infinity>(), tolerance) << order;
  }
}

TEST(ElementScenes, TetOnlyModelsRefuseAHexMesh) {
  std::string text = withLaw("stvk");
  text = std::regex_replace(text, std::regex(R"(\{type: hyperelastic, law: stvk\})"),
                            "{type: edge_length}");
  try {
    sceneFrom(text, "tt_hex_edge_length");
    FAIL() << "edge_length accepted a hex mesh";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("force model 'edge_length' covers tetrahedra only, and "
                                         "the mesh has 32 hexahedra"),
              std::string::npos)
        << e.what();
  }
}

// config/scenes/tongue_sag.yaml: the tongue's slivers (aspect ratio above 50) at 6 kPa.
TEST(ElementScenes, SliverMeshRunsWithNeoHookeanWhereStvkStops) {
  const fs::path file = kRoot / "config/scenes/tongue_sag.yaml";
  Scene handled = loadScene(file.string());
  EXPECT_GT(meshQuality(handled.system.mesh).aspectMax, 50.0);
  const RunSummary nh = runScene(handled, {0.12, "", nullptr});
  EXPECT_TRUE(nh.ok) << nh.failure;
  EXPECT_EQ(nh.frames, 12);
  EXPECT_EQ(nh.guard.failures, 0);

  std::ifstream in(file);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text = std::regex_replace(text, std::regex(R"(  - type: hyperelastic\n    law: neo_hookean\n    inversion_threshold: 0.2[^\n]*)"),
                            "  - type: edge_length");
  text = std::regex_replace(text, std::regex(R"(\.\./meshes/)"), (kRoot / "config/meshes/").string());
  Scene stvk = sceneFrom(text, "tt_tongue_stvk");
  ASSERT_STREQ(stvk.system.models[0]->name(), "edge_length");
  const RunSummary bare = runScene(stvk, {0.12, "", nullptr});
  EXPECT_FALSE(bare.ok) << "the StVK tongue no longer inverts a sliver: the test lost its point";
  EXPECT_NE(bare.failure.find("inverted or flat"), std::string::npos) << bare.failure;
}

// The Adamss pairing of a constitutive law with its volume term ("Adamss: Advanced Anisotropic
// Mass-Spring System", Secs. 2.4.2.3-2.4.2.4): two hyperelastic models on one mesh, the
// volume law's keys in the material. A law key that no model reads is an error.
TEST(ElementScenes, StvkPlusVolumeTermAndUnusedLawKeys) {
  const char* const text = R"(
mesh: {generator: box, nodes: [4, 3, 3], size: [30, 20, 20], length_unit: mm, split: none}
materials: [{young_modulus: 20, stress_unit: kPa, poisson_ratio: 0.3, volume_stiffness: 50}]
force_models: [{type: hyperelastic, law: stvk}, {type: hyperelastic, law: volume}]
integrator: {type: backward_euler}
boundary: {fixed: [{box: {min: [-1, -1, -1], max: [0.001, 1, 1]}}]}
loads: {gravity: [0, 0, -9.81], rayleigh_mass: 5.0}
)";
  Scene scene = sceneFrom(text, "tt_stvk_volume");
  ASSERT_EQ(scene.system.models.size(), 3u);  // two laws and gravity
  const RunSummary run = runScene(scene, {0.2, "", nullptr});
  EXPECT_TRUE(run.ok) << run.failure;

  std::string unused = std::regex_replace(std::string(text), std::regex(R"(, \{type: hyperelastic, law: volume\})"), "");
  try {
    sceneFrom(unused, "tt_unused_law_key");
    FAIL() << "a volume_stiffness no model reads was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("materials[0].volume_stiffness: read by the law 'volume', "
                                         "which no force model of this scene uses"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tt
