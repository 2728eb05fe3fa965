// Each law reads its own constants from a `materials` entry: a Hunter material states only its
// `hunter` map and density (no Young's modulus), loads and runs; the Lame constants reach
// System::materials only when a model reads them, and when none does the loader notes them.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "scene_test_util.h"
#include "tissue_trainer/core/material/elastic_constants.h"
#include "tissue_trainer/core/mesh/quality.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

namespace fs = std::filesystem;
const fs::path kRoot = TT_SOURCE_DIR;

using testutil::replaced;
using testutil::writeScene;

// A 1 cm myocardium cube under gravity, its bottom clamped: the material gives only the density
// and the Hunter constants (Table 2.1 of "Adamss: Advanced Anisotropic Mass-Spring System"),
// through the virtual hexahedron as config/scenes/beating_heart.yaml.
const char* const kHunterOnly = R"(name: hunter_only
mesh: {generator: box, nodes: [3, 3, 3], size: [0.01, 0.01, 0.01], split: six_mirrored}
fibres: {direction: [1, 0, 0]}
materials:
  - density: 1060
    stress_unit: kPa
    hunter:
      k: [2.842, 0.063, 0.31, 1.0, 1.0, 1.0]
      a: [0.318, 0.429, 1.037, 0.731, 0.731, 0.886]
      b: [0.624, 2.48, 0.398, 2.0, 2.0, 2.0]
force_models:
  - {type: virtual_hexahedron, law: hunter}
integrator: {type: backward_euler}
boundary:
  fixed:
    - plane: {point: [0, 0, 0], normal: [0, 0, 1]}
loads: {gravity: [0, -9.81, 0], rayleigh_mass: 20}
run: {frame_time: 0.005, duration: 0.1}
)";

double totalMass(const System& s) { return s.mass.sum() / 3.0; }

TEST(MaterialOwnConstants, HunterMaterialWithoutYoungModulusLoadsAndRuns) {
  Scene scene = loadScene(writeScene("hunter_only.yaml", kHunterOnly));
  const System& s = scene.system;
  EXPECT_FALSE(s.materials[0].elastic.has_value()) << "no model reads Lame constants here";
  EXPECT_TRUE(scene.notes.empty()) << scene.notes.front();
  // The density is read: the lumped masses add up to rho V.
  EXPECT_NEAR(totalMass(s), 1060.0 * 1e-6, 1e-12);

  const Eigen::VectorXd rest = s.state.x;
  for (int frame = 0; frame < 20; ++frame) {
    const StepReport r = scene.integrator->advance(scene.system, scene.frameTime);
    ASSERT_TRUE(r.ok) << "frame " << frame << ": " << r.failure;
  }
  const Eigen::VectorXd& x = scene.system.state.x;
  ASSERT_TRUE(x.allFinite());
  // Gravity along -y bends the cube: the free top moves down in y, by less than its size.
  double topShift = 0.0;
  for (int n = 0; n < s.numNodes(); ++n)
    if (s.mesh.rest(2, n) > 0.0099) topShift = std::min(topShift, x(3 * n + 1) - rest(3 * n + 1));
  EXPECT_LT(topShift, -1e-7);
  EXPECT_GT(topShift, -0.01);
}

TEST(MaterialOwnConstants, LameConstantsReachTheMaterialsWhenAModelReadsThem) {
  const std::string stvk = replaced(
      replaced(kHunterOnly, "  - {type: virtual_hexahedron, law: hunter}",
               "  - {type: hyperelastic, law: stvk}"),
      "    hunter:\n      k: [2.842, 0.063, 0.31, 1.0, 1.0, 1.0]\n"
      "      a: [0.318, 0.429, 1.037, 0.731, 0.731, 0.886]\n"
      "      b: [0.624, 2.48, 0.398, 2.0, 2.0, 2.0]\n",
      "    young_modulus: 20\n    poisson_ratio: 0.3\n");
  const Scene scene = loadScene(writeScene("stvk_block.yaml", stvk));
  ASSERT_TRUE(scene.system.materials[0].elastic.has_value());
  // E = 20 kPa, nu = 0.3: mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)).
  EXPECT_NEAR(scene.system.materials[0].elastic->mu, 20e3 / 2.6, 1e-9);
  EXPECT_NEAR(scene.system.materials[0].elastic->lambda, 20e3 * 0.3 / (1.3 * 0.4), 1e-9);
  EXPECT_TRUE(scene.notes.empty());
}

TEST(MaterialOwnConstants, UnreadLameConstantsAreNotedByName) {
  const std::string withModulus =
      replaced(kHunterOnly, "  - density: 1060\n",
               "  - density: 1060\n    young_modulus: 3\n    poisson_ratio: 0.4\n");
  const Scene scene = loadScene(writeScene("hunter_with_modulus.yaml", withModulus));
  ASSERT_EQ(scene.notes.size(), 1u);
  const std::string& note = scene.notes[0];
  EXPECT_NE(note.find("materials[0]"), std::string::npos) << note;
  EXPECT_NE(note.find("young_modulus, poisson_ratio"), std::string::npos) << note;
  EXPECT_NE(note.find("read by no force model"), std::string::npos) << note;
  EXPECT_FALSE(scene.system.materials[0].elastic.has_value());
}

// Every shipped scene loads and states only constants its models read.
TEST(MaterialOwnConstants, ShippedScenesStateOnlyWhatTheirLawsRead) {
  int loaded = 0;
  for (const auto& file : fs::directory_iterator(kRoot / "config/scenes")) {
    if (file.path().extension() != ".yaml") continue;
    const Scene scene = loadScene(file.path().string());
    for (const std::string& note : scene.notes)
      EXPECT_EQ(note.find("read by no force model"), std::string::npos)
          << file.path().filename() << ": " << note;
    ++loaded;
  }
  EXPECT_GE(loaded, 9);  // config/scenes holds 9 today
  const Scene heart = loadScene((kRoot / "config/scenes/beating_heart.yaml").string());
  EXPECT_FALSE(heart.system.materials[0].elastic.has_value());
}

// The project's own headers a file includes ("tissue_trainer/core/ROOM/FILE.h" -> ROOM/FILE.h).
std::vector<std::string> coreIncludes(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> out;
  const std::string prefix = "#include \"tissue_trainer/core/";
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0)
      out.push_back(line.substr(prefix.size(), line.find('"', prefix.size()) - prefix.size()));
  return out;
}

// Every file of a room of the core, sources and headers.
std::vector<fs::path> roomFiles(const std::string& room) {
  std::vector<fs::path> files;
  for (const fs::path root :
       {kRoot / "src/core" / room, kRoot / "include/tissue_trainer/core" / room})
    for (const auto& file : fs::recursive_directory_iterator(root))
      if (file.is_regular_file()) files.push_back(file.path());
  return files;
}

// scene/ (the loader and the runner) is the core's top: no other room includes it.
TEST(CoreLayers, NoRoomBelowTheSceneIncludesIt) {
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(kRoot / "src/core")) {
    const std::string room = entry.path().filename().string();
    if (!entry.is_directory() || room == "scene") continue;
    for (const fs::path& file : roomFiles(room)) {
      for (const std::string& header : coreIncludes(file))
        EXPECT_NE(header.rfind("scene/", 0), 0u) << file << " includes " << header;
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);  // 222 files when written
}

// registry/ sits below the models, laws and integrators that register in it: it knows their
// interfaces, the data they are built over and the rooms below it (mesh/, and solve/ for the
// linear-solve settings its key reader fills), nothing of any model, law or integrator.
TEST(CoreLayers, TheRegistryKnowsOnlyTheInterfaces) {
  const std::vector<std::string> interfaces{"error.h", "integrate/integrator.h",
                                            "material/elastic_constants.h",
                                            "model/force_model.h", "model/material.h"};
  const std::vector<std::string> roomsBelow{"registry/", "mesh/", "solve/"};
  int checked = 0;
  for (const fs::path& file : roomFiles("registry"))
    for (const std::string& header : coreIncludes(file)) {
      const bool below = std::any_of(roomsBelow.begin(), roomsBelow.end(),
                                     [&](const std::string& room) {
                                       return header.rfind(room, 0) == 0;
                                     });
      const bool interface =
          std::find(interfaces.begin(), interfaces.end(), header) != interfaces.end();
      EXPECT_TRUE(below || interface) << file << " includes " << header;
      ++checked;
    }
  EXPECT_GT(checked, 10);
}

}  // namespace
}  // namespace tt
