// Bad collision entries: each gives one InputError naming the file, the line and the key.
// (Built again under AddressSanitizer + UBSan by scripts/test.)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scene_test_util.h"

namespace tt {
namespace {

// Line numbers below refer to this text.
const char* const kCollisionScene = R"(name: collision
mesh: {generator: box, nodes: [3, 3, 3], size: [0.01, 0.01, 0.01]}
materials:
  - {young_modulus: 10, poisson_ratio: 0.3, stress_unit: kPa}
force_models:
  - {type: hyperelastic, law: neo_hookean}
  - type: collision
    stiffness: 1000
    nodes: surface
    bodies:
      - plane: {point: [0, 0, -0.001], normal: [0, 0, 1]}
      - sphere: {centre: [0, 0, 0.02], radius: 0.005}
integrator: {type: quasistatic}
)";

using testutil::BadScene;
using testutil::replaced;

TEST(MalformedCollision, GoodSceneLoads) {
  EXPECT_NO_THROW(loadScene(testutil::writeScene("collision_good.yaml", kCollisionScene)));
}

TEST(MalformedCollision, EachErrorNamesFileLineAndKey) {
  const std::string dir =
      std::filesystem::path(testutil::writeScene("collision_good.yaml", kCollisionScene)).parent_path();
  std::ofstream(dir + "/open_box.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 3 2\nf 1 4 3\n";
  const std::string s = kCollisionScene;
  const std::vector<BadScene> cases = {
      {"unknown key", replaced(s, "    nodes: surface", "    node: surface"), 9,
       "force_models[1].node: unknown key 'node'"},
      {"no stiffness", replaced(s, "    stiffness: 1000\n", ""), 7,
       "force_models[1]: missing required key 'stiffness'"},
      {"negative stiffness", replaced(s, "stiffness: 1000", "stiffness: -5"), 8,
       "force_models[1].stiffness: expected a positive number, got '-5'"},
      {"unknown node word", replaced(s, "nodes: surface", "nodes: boundary"), 9,
       "force_models[1].nodes: expected one of: surface, all; got 'boundary'"},
      {"selection matching no node",
       replaced(s, "nodes: surface", "nodes: {box: {min: [1, 1, 1], max: [2, 2, 2]}}"), 9,
       "force_models[1].nodes: the selection matches no node"},
      {"two selections",
       replaced(s, "nodes: surface", "nodes: {nodes: [0], region: all}"), 9,
       "force_models[1].nodes: expected one of 'box', 'plane', 'nodes' or 'region'"},
      {"empty region", replaced(s, "nodes: surface", "nodes: {region: {box: {min: [1, 1, 1], max: [2, 2, 2]}}}"), 9,
       "force_models[1].nodes.region: the region contains no element"},
      {"no bodies", replaced(s, "    bodies:\n      - plane: {point: [0, 0, -0.001], normal: [0, 0, 1]}\n"
                                "      - sphere: {centre: [0, 0, 0.02], radius: 0.005}\n",
                             "    bodies: []\n"),
       10, "force_models[1].bodies: expected at least one body"},
      {"zero normal", replaced(s, "normal: [0, 0, 1]", "normal: [0, 0, 0]"), 11,
       "force_models[1].bodies[0].plane.normal: expected a non-zero normal"},
      {"zero radius", replaced(s, "radius: 0.005", "radius: 0"), 12,
       "force_models[1].bodies[1].sphere.radius: expected a positive number, got '0'"},
      {"misspelt centre", replaced(s, "centre:", "center:"), 12,
       "force_models[1].bodies[1].sphere.center: unknown key 'center'"},
      {"two kinds in one body",
       replaced(s, "      - sphere: {centre: [0, 0, 0.02], radius: 0.005}",
                "      - sphere: {centre: [0, 0, 0.02], radius: 0.005}\n        plane: {point: [0, 0, 0], normal: [1, 0, 0]}"),
       12, "force_models[1].bodies[1]: expected exactly one of 'plane', 'sphere' or 'mesh'"},
      {"unknown body", replaced(s, "      - sphere:", "      - capsule:"), 12,
       "force_models[1].bodies[1].capsule: unknown key 'capsule'"},
      {"missing mesh file",
       replaced(s, "      - sphere: {centre: [0, 0, 0.02], radius: 0.005}", "      - mesh: {file: nowhere.obj}"),
       12, "force_models[1].bodies[1].mesh.file: surface file"},
      {"open mesh",
       replaced(s, "      - sphere: {centre: [0, 0, 0.02], radius: 0.005}", "      - mesh: {file: open_box.obj}"),
       12, "force_models[1].bodies[1].mesh.file: expected a closed, consistently oriented surface: edge"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_collision.yaml");
}

}  // namespace
}  // namespace tt
