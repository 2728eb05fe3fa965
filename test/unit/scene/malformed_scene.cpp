// Bad scene files: each gives one InputError naming the file, the line and the key path.
// (Built again under AddressSanitizer + UBSan by scripts/test.)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "scene_test_util.h"
#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

const char* const kGoodScene = R"(name: block
mesh:
  generator: box
  nodes: [3, 3, 3]
  size: [0.02, 0.02, 0.02]
materials:
  - young_modulus: 3
    stress_unit: kPa
    poisson_ratio: 0.4
    density: 1000
force_models:
  - type: edge_length
integrator:
  type: backward_euler
  substeps: 1
boundary:
  fixed:
    - plane: {point: [0, 0, 0], normal: [0, 0, 1]}
loads:
  gravity: [0, 0, -9.81]
run: {frame_time: 0.01, duration: 0.05}
)";

using testutil::writeScene;

// Replaces the first occurrence of `from` in the good scene.
std::string edited(const std::string& from, const std::string& to) {
  std::string text = kGoodScene;
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

using testutil::BadScene;

TEST(MalformedScene, GoodSceneLoads) {
  const Scene scene = loadScene(writeScene("good.yaml", kGoodScene));
  EXPECT_EQ(scene.system.numNodes(), 27);
  EXPECT_EQ(scene.system.models.size(), 2u);  // edge_length + gravity (listed under loads)
  EXPECT_EQ(scene.system.constrainedDofs.size(), 27u);  // 9 nodes on z = 0, all axes
  EXPECT_DOUBLE_EQ(scene.system.materials[0].elastic->mu, 3000.0 / (2 * 1.4));
}

TEST(MalformedScene, EachErrorNamesFileLineAndKey) {
  const std::vector<BadScene> cases = {
      {"unknown top-level key", edited("run:", "rn:"), 21, "unknown key 'rn'"},
      {"typo in a nested key", edited("poisson_ratio", "poison_ratio"), 9, "materials[0].poison_ratio"},
      {"non-numeric modulus", edited("young_modulus: 3", "young_modulus: three"), 7, "expected a finite number"},
      {"negative modulus", edited("young_modulus: 3", "young_modulus: -3"), 7, "expected a positive number"},
      {"Poisson ratio 0.5", edited("poisson_ratio: 0.4", "poisson_ratio: 0.5"), 9, "(-1, 0.5)"},
      {"Poisson ratio -1", edited("poisson_ratio: 0.4", "poisson_ratio: -1"), 9, "(-1, 0.5)"},
      {"missing mesh file", edited("generator: box\n  nodes: [3, 3, 3]\n  size: [0.02, 0.02, 0.02]", "file: no_such.msh"), 3, "not found"},
      {"unknown generator", edited("generator: box", "generator: sphere"), 3, "box, cantilever, spindle"},
      {"two node counts", edited("[3, 3, 3]", "[3, 3]"), 4, "3 node counts"},
      {"empty node set", edited("point: [0, 0, 0]", "point: [0, 0, -1]"), 18, "matches no node"},
      {"unknown model", edited("type: edge_length", "type: edge_lenght"), 12, "force_models[0].type"},
      {"unknown integrator", edited("type: backward_euler", "type: rk4"), 14, "integrator.type"},
      {"zero substeps", edited("substeps: 1", "substeps: 0"), 15, "integer >= 1"},
      {"missing force models", edited("force_models:\n  - type: edge_length\n", ""), 0, "missing required key 'force_models'"},
      {"bad axes", edited("normal: [0, 0, 1]}", "normal: [0, 0, 1]}\n      axes: xq"), 19, "combination of x, y and z"},
      {"gravity not a vector", edited("[0, 0, -9.81]", "down"), 20, "list of 3 numbers"},
      {"infinite number", edited("density: 1000", "density: .inf"), 10, "finite number"},
      {"invalid YAML", edited("name: block", "name: [block"), 0, "not valid YAML"},
      {"empty file", "", 0, "expected a map"},
      {"binary garbage", std::string("\x01\x02\xff\xfe{{[[\x00\x7f", 10), 0, ""},
      {"tendon wider than the belly", edited("generator: box\n  nodes: [3, 3, 3]\n  size: [0.02, 0.02, 0.02]", "generator: spindle\n  max_radius: 0.01\n  tendon_radius: 0.02"), 5, "tendon_radius < max_radius"},
      {"two spindle segments", edited("generator: box\n  nodes: [3, 3, 3]\n  size: [0.02, 0.02, 0.02]", "generator: spindle\n  segments: 2"), 4, "mesh.segments"},
      {"translate of two numbers", edited("size: [0.02, 0.02, 0.02]", "size: [0.02, 0.02, 0.02]\n  translate: [1, 2]"), 6, "mesh.translate"},
      {"rotate_deg not numbers", edited("size: [0.02, 0.02, 0.02]", "size: [0.02, 0.02, 0.02]\n  rotate_deg: [a, 0, 0]"), 6, "mesh.rotate_deg"},
      {"unknown contact key", edited("run:", "contact: {stiffnes: 100}\nrun:"), 21, "contact.stiffnes"},
      {"negative contact stiffness", edited("run:", "contact: {stiffness: -100}\nrun:"), 21, "contact.stiffness: expected a positive number"},
      {"both contact stiffnesses", edited("run:", "contact: {stiffness: 100, stiffness_per_area: 1e6}\nrun:"), 21, "contact.stiffness_per_area: give either stiffness"},
      {"negative contact stiffness per area", edited("run:", "contact: {stiffness_per_area: -1e6}\nrun:"), 21, "contact.stiffness_per_area: expected a positive number"},
      {"sample spacing without the per-area contact", edited("run:", "contact: {sample_spacing: 1e-3}\nrun:"), 21, "contact.sample_spacing: is for the contact per unit area"},
      {"zero sample spacing", edited("run:", "contact: {stiffness_per_area: 1e6, sample_spacing: 0}\nrun:"), 21, "contact.sample_spacing: expected a positive number"},
      {"negative contact damping", edited("run:", "contact: {damping: -1}\nrun:"), 21, "contact.damping"},
      {"grasp angle out of range", edited("run:", "contact: {grasp_jaw_angle: 4}\nrun:"), 21, "[0, pi]"},
      {"unknown felt stiffness", edited("run:", "contact: {felt_stiffness: tissue}\nrun:"), 21, "contact.felt_stiffness: expected one of"},
      {"zero grasp nodes", edited("run:", "contact: {grasp_max_nodes: 0}\nrun:"), 21, "contact.grasp_max_nodes"},
      {"zero tool speed", edited("run:", "contact: {tool_max_speed: 0}\nrun:"), 21, "contact.tool_max_speed: expected a speed > 0 (m/s), got 0"},
      {"tool speed not a number", edited("run:", "contact: {tool_max_speed: fast}\nrun:"), 21, "contact.tool_max_speed: expected a finite number"},
      {"infinite tool speed", edited("run:", "contact: {tool_max_speed: .inf}\nrun:"), 21, "contact.tool_max_speed: expected a finite number"},
      {"contact not a map", edited("run:", "contact: 100\nrun:"), 21, "contact"},
      {"missing render surface", edited("run:", "render_surface: {file: none.obj}\nrun:"), 21, "not found"},
      {"render surface without file", edited("run:", "render_surface: {outside: clamp}\nrun:"), 21, "missing required key 'file'"},
      {"bad outside policy", edited("run:", "render_surface: {file: none.obj, outside: snap}\nrun:"), 21, "render_surface"},
      {"unknown guard key", edited("run:", "stability_guard: {max_halving: 3}\nrun:"), 21, "stability_guard.max_halving: unknown key"},
      {"guard not a map", edited("run:", "stability_guard: on\nrun:"), 21, "stability_guard: expected a map, got 'on'"},
      {"negative halvings", edited("run:", "stability_guard: {max_halvings: -1}\nrun:"), 21, "stability_guard.max_halvings: expected an integer in [0, 16], got '-1'"},
      {"too many halvings", edited("run:", "stability_guard: {max_halvings: 17}\nrun:"), 21, "[0, 16], got '17'"},
      {"fractional halvings", edited("run:", "stability_guard: {max_halvings: 2.5}\nrun:"), 21, "[0, 16], got '2.5'"},
      {"energy growth of 1", edited("run:", "stability_guard: {energy_growth: 1}\nrun:"), 21, "stability_guard.energy_growth: expected a number > 1, got '1'"},
      {"energy growth not a number", edited("run:", "stability_guard: {energy_growth: lots}\nrun:"), 21, "stability_guard.energy_growth: expected a finite number"},
      {"negative energy slack", edited("run:", "stability_guard: {energy_slack: -1e-9}\nrun:"), 21, "stability_guard.energy_slack: expected a non-negative energy (J)"},
      {"volume ratio of 1", edited("run:", "stability_guard: {min_volume_ratio: 1}\nrun:"), 21, "stability_guard.min_volume_ratio: expected a volume ratio in [0, 1)"},
      {"guard enabled not a boolean", edited("run:", "stability_guard:\n  enabled: maybe\nrun:"), 22, "stability_guard.enabled: expected true or false"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad.yaml");
}

// TetGen files: three good tets and a flat one (tet 3, in the plane z = 0) whose nodes the
// good tets share, or, with `orphan`, whose fourth node is its own.
std::string writeFlatTetMesh(const std::string& name, bool orphan) {
  const fs::path dir = fs::temp_directory_path() / "tt_scene_tests";
  fs::create_directories(dir);
  std::ofstream(dir / (name + ".node")) << "7 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n"
                                           "4 1 1 0\n5 1 1 1\n6 0.4 0.4 0\n";
  std::ofstream(dir / (name + ".ele")) << "4 4 0\n0 0 1 2 3\n1 1 4 2 3\n2 4 2 3 5\n3 0 1 2 "
                                       << (orphan ? 6 : 4) << "\n";
  return (dir / (name + ".ele")).string();
}

TEST(MalformedScene, AFlatTetIsNamedOrDroppedWhenTheSceneSaysSo) {
  const std::string box = "generator: box\n  nodes: [3, 3, 3]\n  size: [0.02, 0.02, 0.02]";
  const std::string shared = writeFlatTetMesh("flat_shared", false);
  const std::string orphan = writeFlatTetMesh("flat_orphan", true);
  const auto message = [](const std::string& text) -> std::string {
    try {
      loadScene(writeScene("flat.yaml", text));
    } catch (const InputError& e) {
      EXPECT_GT(e.line(), 0);
      return e.what();
    }
    return "";
  };
  const std::string refused = message(edited(box, "file: " + shared));
  EXPECT_NE(refused.find("1 flat tet(s)"), std::string::npos) << refused;
  EXPECT_NE(refused.find("tet 3 (nodes 0 1 2 4, normalised volume 0)"), std::string::npos) << refused;
  EXPECT_NE(refused.find("drop_degenerate: true"), std::string::npos) << refused;
  EXPECT_EQ(refused.find('\n'), std::string::npos) << refused;

  const Scene dropped = loadScene(writeScene("flat.yaml", edited(box, "file: " + shared + "\n  drop_degenerate: true")));
  EXPECT_EQ(dropped.system.mesh.numTets(), 3);
  EXPECT_EQ(dropped.system.mesh.material.size(), 3u);
  bool noted = false;
  for (const std::string& note : dropped.notes) noted = noted || note.find("dropped 1 flat tet") != std::string::npos;
  EXPECT_TRUE(noted);

  const std::string orphaned = message(edited(box, "file: " + orphan + "\n  drop_degenerate: true"));
  EXPECT_NE(orphaned.find("node 6 belongs to no element"), std::string::npos) << orphaned;
}

TEST(MalformedScene, MissingSceneFileIsOneClearError) {
  try {
    loadScene("/nonexistent/scene.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/scene.yaml: cannot open the scene file");
  }
}

}  // namespace
}  // namespace tt
