// Malformed adamss_cavity and adamss_lms_volume_springs entries: each is one InputError naming
// the file, the line and the key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_util.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

using testutil::BadScene;
using testutil::replaced;

// Line numbers below refer to this text. The box's node (i, j, k) is i + 2 j + 4 k.
const char* const kCavityScene = R"(name: cavity
mesh: {generator: box, nodes: [2, 2, 2], size: [0.01, 0.01, 0.01], split: six}
materials:
  - {young_modulus: 3000, poisson_ratio: 0.4}
force_models:
  - {type: hyperelastic, law: neo_hookean}
  - type: adamss_cavity
    faces: [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    pressure: 1.0
integrator: {type: backward_euler}
)";

const std::string kFaces =
    "[[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]";

std::string withFaces(const std::string& faces) { return replaced(kCavityScene, kFaces, faces); }

std::string withLine9(const std::string& line) {
  return replaced(kCavityScene, "    pressure: 1.0\n", line);
}

std::string withLms(const std::string& entry) {
  return replaced(kCavityScene,
                  "  - type: adamss_cavity\n    faces: " + kFaces + "\n    pressure: 1.0\n",
                  entry);
}

TEST(MalformedCavity, TheGoodScenesLoad) {
  const Scene scene = loadScene(testutil::writeScene("cavity_good.yaml", kCavityScene));
  EXPECT_STREQ(scene.system.models.at(1)->name(), "adamss_cavity");
  const std::string surface = replaced(
      kCavityScene, "faces: " + kFaces, "surface: {box: {min: [-1, -1, -1], max: [1, 1, 1]}}");
  EXPECT_NO_THROW(loadScene(testutil::writeScene("cavity_surface.yaml", surface)));
  const Scene lms = loadScene(testutil::writeScene(
      "lms_good.yaml",
      replaced(withLms("  - {type: adamss_lms_volume_springs, stiffness: 10, rate: 1e9}\n"),
               "{type: backward_euler}", "{type: symplectic_euler, time_step: 1e-5}")));
  EXPECT_TRUE(lms.system.models.at(1)->needsStepUpdates());
}

TEST(MalformedCavity, EachErrorNamesFileLineAndKey) {
  const std::vector<BadScene> cases = {
      {"misspelt key", withLine9("    presure: 1.0\n"), 9, "presure"},
      {"both facet sources",
       withLine9("    pressure: 1.0\n    surface: {box: {min: [0, 0, 0], max: [1, 1, 1]}}\n"), 7,
       "expected exactly one of 'faces'"},
      {"no facets", replaced(kCavityScene, "    faces: " + kFaces + "\n", ""), 7,
       "expected exactly one of 'faces'"},
      {"open surface",
       withFaces("[[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2]]"), 8,
       "edge (1, 3) belongs to 1 facets"},
      {"inconsistent orientation",
       withFaces("[[1, 3, 2, 0], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]"),
       8, "run along it the same way"},
      {"a facet of two nodes",
       withFaces("[[0, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]"),
       8, "expected a facet of 3 or 4 node indices"},
      {"node out of range",
       withFaces("[[0, 2, 3, 9], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]"),
       8, "node 9 is not in [0, 7]"},
      {"facets not a list", withFaces("all"), 8, "faces"},
      {"pressure not a number", withLine9("    pressure: high\n"), 9, "pressure"},
      {"pressure a list", withLine9("    pressure: [1, 2]\n"), 9, "pressure"},
      {"pressure curve of an unknown type", withLine9("    pressure: {type: sine, value: 1}\n"), 9,
       "sine"},
      {"pressure curve without its keys", withLine9("    pressure: {type: piecewise_linear}\n"),
       9, "times"},
      {"negative volume stiffness", withLine9("    pressure: 1.0\n    volume_stiffness: -1\n"), 10,
       "expected a volume stiffness >= 0"},
      {"zero target ratio", withLine9("    pressure: 1.0\n    target_volume_ratio: 0\n"), 10,
       "target_volume_ratio"},
      {"unknown stress unit", withLine9("    pressure: 1.0\n    stress_unit: kpa\n"), 10,
       "stress_unit"},
      {"a cavity doing nothing", withLine9(""), 7, "expected a non-zero pressure or volume_stiffness"},
      {"surface selecting one face",
       replaced(kCavityScene, "faces: " + kFaces,
                "surface: {box: {min: [-1, -1, -1], max: [1, 1, 0.001]}}"),
       8, "belongs to 1 facets"},
      {"surface selecting no face",
       replaced(kCavityScene, "faces: " + kFaces, "surface: {nodes: [0, 7]}"), 8,
       "no boundary face of the mesh has all its nodes selected"},
      {"surface with an unknown selection",
       replaced(kCavityScene, "faces: " + kFaces, "surface: {sphere: {radius: 1}}"), 8, "sphere"},
      {"lms without rate", withLms("  - {type: adamss_lms_volume_springs, stiffness: 10}\n"), 7,
       "rate"},
      {"lms negative rate",
       withLms("  - {type: adamss_lms_volume_springs, stiffness: 10, rate: -1}\n"), 7,
       "expected a rate >= 0"},
      {"lms misspelt update",
       withLms("  - {type: adamss_lms_volume_springs, stiffness: 10, rate: 1, update: strian}\n"),
       7, "strian"},
      {"lms zero stiffness",
       withLms("  - {type: adamss_lms_volume_springs, stiffness: 0, rate: 1}\n"), 7, "stiffness"},
  };
  testutil::expectEachSceneFailsClearly(cases, "malformed_cavity.yaml");
}

}  // namespace
}  // namespace tt
