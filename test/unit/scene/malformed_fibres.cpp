// Malformed fibre input: each bad row of a fibre file, a wrong number of rows and each bad
// `fibres` key (top level or in a material) is one InputError naming the file and the line.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_util.h"
#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/mesh/fibre_field.h"

namespace tt {
namespace {

using testutil::BadScene;
using testutil::replaced;
using testutil::writeScene;

TEST(MalformedFibreFile, EachBadRowIsOneLineNamingFileAndLine) {
  const std::string good = "0 90\n1 0 0 0 1 0\n";
  const std::vector<BadScene> cases = {
      {"four values", good + "1 0 0 1\n", 3, "expected 6 numbers (fibre x y z, sheet x y z) or 2 angles"},
      {"not a number", "0 90\n1 0 zero 0 1 0\n0 90\n", 2, "'zero'"},
      {"infinite", "0 90\n1 0 1e999 0 1 0\n0 90\n", 2, "1e999"},
      {"zero fibre", "# frames\n\n0 0 0 0 1 0\n0 90\n0 90\n", 3, "expected a non-zero fibre vector"},
      {"zero sheet", good + "0 0 1 0 0 0\n", 3, "expected a non-zero sheet vector"},
      {"parallel", good + "0 0 1 0 0 -2\n", 3, "expected a sheet vector not parallel to the fibre"},
      {"too few rows", good + "# the end\n", 2, "expected 3 rows (one per element: tets, then hexes), the file ends after 2"},
      {"too many rows", good + "0 90\n0 45\n", 4, "expected 3 rows (one per element: tets, then hexes), found more"},
  };
  testutil::expectEachFileFailsClearly(
      cases, "bad_frames.txt", [](const std::string& path) { readFibreFile(path, 3); });
  EXPECT_EQ(readFibreFile(writeScene("good_frames.txt", good + "0 45\n"), 3).size(), 3u);
}

// Line numbers refer to this text (the mesh has 8 hexes).
const char* const kFibreScene = R"(mesh: {generator: box, nodes: [3, 3, 3], size: [0.01, 0.01, 0.01], split: none}
fibres: FIBRES
materials:
  - young_modulus: 3000
    poisson_ratio: 0.3
  - region: {box: {min: [-1, -1, 0.005], max: [1, 1, 1]}}
    young_modulus: 3000
    poisson_ratio: 0.3
    fibres: REGION
force_models: [{type: edge_length}]
integrator: {type: explicit_euler, time_step: 1.0e-5}
)";

std::string with(const std::string& fibres, const std::string& region = "{direction: [1, 0, 0]}") {
  return replaced(replaced(kFibreScene, "FIBRES", fibres), "REGION", region);
}

TEST(MalformedFibreScene, EachBadKeyIsOneLineNamingFileLineAndKey) {
  const std::string transmural = "{transmural: {normal: [0, 0, 1], direction: [1, 0, 0], angles_deg: [60, -60]}}";
  const std::vector<BadScene> cases = {
      {"file missing", with("{file: no_such_frames.txt}"), 2, "fibres.file: fibre file"},
      {"file and transmural",
       with("{file: f.txt, transmural: {normal: [0, 0, 1], direction: [1, 0, 0], angles_deg: [0, 0]}}"),
       2, "expected one form of fibres"},
      {"direction and transmural",
       with("{direction: [1, 0, 0], transmural: {normal: [0, 0, 1], direction: [1, 0, 0], angles_deg: [0, 0]}}"),
       2, "fibres.transmural: expected one form of fibres"},
      {"zero normal", replaced(with(transmural), "normal: [0, 0, 1]", "normal: [0, 0, 0]"), 2,
       "fibres.transmural.normal: expected a non-zero wall normal"},
      {"direction along the normal", replaced(with(transmural), "direction: [1, 0, 0], angles", "direction: [0, 0, -3], angles"),
       2, "fibres.transmural.direction: expected a non-zero fibre direction not parallel to the normal"},
      {"one angle", replaced(with(transmural), "angles_deg: [60, -60]", "angles_deg: [60]"), 2,
       "fibres.transmural.angles_deg: expected a list of 2 angles"},
      {"no angles", replaced(with(transmural), ", angles_deg: [60, -60]", ""), 2,
       "fibres.transmural: missing required key 'angles_deg'"},
      {"reversed extent", replaced(with(transmural), "-60]}", "-60], extent: [0.01, 0]}"), 2,
       "fibres.transmural.extent: expected from < to"},
      {"unknown transmural key", replaced(with(transmural), "-60]}", "-60], centre: [0, 0, 0]}"), 2,
       "fibres.transmural.centre: unknown key 'centre'"},
      {"file in a material", with("{direction: [1, 0, 0]}", "{file: frames.txt}"), 9,
       "materials[1].fibres.file: unknown key 'file'"},
      {"bad material frame", with("{direction: [1, 0, 0]}", "{direction: [0, 0, 0]}"), 9,
       "materials[1].fibres.direction: expected a non-zero direction"},
      {"material without elements",
       replaced(replaced(with("{direction: [1, 0, 0]}"), "min: [-1, -1, 0.005]", "min: [-1, -1, -1]"),
                "    poisson_ratio: 0.3\n  - region", "    poisson_ratio: 0.3\n    fibres: {direction: [0, 1, 0]}\n  - region"),
       6, "materials[0].fibres: no element has this material"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_fibres.yaml");
}

// A row count that does not match the mesh names the fibre file, not the scene.
TEST(MalformedFibreScene, FileWithTooFewRowsNamesTheFibreFile) {
  std::string rows;
  for (int e = 0; e < 7; ++e) rows += "0 90\n";
  const std::string frames = writeScene("seven_frames.txt", rows);
  const std::string scene = writeScene("short_file.yaml", with("{file: seven_frames.txt}"));
  try {
    loadScene(scene);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), frames);
    EXPECT_EQ(e.line(), 7) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected 8 rows"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tt
