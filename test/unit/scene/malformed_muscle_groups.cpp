// Bad muscle_groups entries: each gives one InputError naming the file, the line and the key.
// (Built again under AddressSanitizer + UBSan by scripts/test.)
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_util.h"

namespace tt {
namespace {

// Line numbers below refer to this text.
const char* const kMuscleGroupScene = R"(name: muscles
mesh: {generator: box, nodes: [3, 3, 3], size: [0.01, 0.01, 0.01]}
materials:
  - young_modulus: 20
    poisson_ratio: 0.45
    stress_unit: kPa
    teran_muscle: {peak_stress: 4}
force_models:
  - type: muscle_groups
    law: teran_muscle
    muscles:
      - name: first
        region: {box: {min: [-1, -1, -1], max: [1, 1, 0.005]}}
        fibres: {direction: [1, 0, 0]}
        activation: 0.5
      - name: second
        region: {elements: [30, 31, 32]}
        activation: 0
integrator: {type: quasistatic}
)";

using testutil::BadScene;
using testutil::replaced;

TEST(MalformedMuscleGroups, GoodSceneLoads) {
  EXPECT_NO_THROW(loadScene(testutil::writeScene("muscles_good.yaml", kMuscleGroupScene)));
}

TEST(MalformedMuscleGroups, EachErrorNamesFileLineAndKey) {
  const std::string s = kMuscleGroupScene;
  const std::vector<BadScene> cases = {
      {"unknown muscle key", replaced(s, "        activation: 0.5", "        activaton: 0.5"), 15,
       "force_models[0].muscles[0].activaton: unknown key 'activaton'"},
      {"region matching no element",
       replaced(s, "max: [1, 1, 0.005]", "max: [1, 1, -0.5]"), 13,
       "force_models[0].muscles[0].region: the region contains no element"},
      {"element outside the mesh", replaced(s, "[30, 31, 32]", "[30, 31, 320]"), 17,
       "force_models[0].muscles[1].region.elements[2]: expected an element index in [0, 39]"},
      {"duplicate names", replaced(s, "name: second", "name: first"), 16,
       "force_models[0].muscles[1].name: expected a name not used by another muscle, got 'first' twice"},
      {"activation above 1", replaced(s, "activation: 0.5", "activation: 1.5"), 15,
       "force_models[0].muscles[0].activation: expected an activation in [0, 1], got '1.5'"},
      {"negative activation", replaced(s, "activation: 0\n", "activation: -0.1\n"), 18,
       "force_models[0].muscles[1].activation: expected an activation in [0, 1], got '-0.1'"},
      {"curve leaving [0, 1]",
       replaced(s, "activation: 0.5",
                "activation: {type: piecewise_linear, times: [0, 1], values: [0, 2]}"),
       15, "force_models[0].muscles[0].activation.values[1]: expected an activation in [0, 1], got '2'"},
      {"twitch peak above 1",
       replaced(s, "activation: 0.5",
                "activation: {type: twitch, period: 1, peak: 3, rise_time: 0.1, decay_time: 0.2}"),
       15, "force_models[0].muscles[0].activation.peak: expected an activation in [0, 1], got '3'"},
      {"overlapping muscles", replaced(s, "[30, 31, 32]", "[0, 1, 2]"), 17,
       "force_models[0].muscles[1].region: expected elements of no other muscle: element 0 is also in muscle 'first'"},
      {"no muscles", s.substr(0, s.find("    muscles:")) + "    muscles: []\nintegrator: {type: quasistatic}\n",
       11, "force_models[0].muscles: expected at least one muscle"},
      {"another law", replaced(s, "law: teran_muscle", "law: neo_hookean"), 10,
       "force_models[0].law: expected one of: teran_muscle; got 'neo_hookean'"},
      {"no law", replaced(s, "    law: teran_muscle\n", ""), 9,
       "force_models[0]: missing required key 'law'"},
      {"activation in the material",
       replaced(s, "teran_muscle: {peak_stress: 4}", "teran_muscle: {peak_stress: 4, activation: 0.2}"), 7,
       "materials[0].teran_muscle.activation: muscle_groups takes the activations from its 'muscles' list"},
      {"bad fibres key", replaced(s, "fibres: {direction: [1, 0, 0]}", "fibres: {file: f.txt}"), 14,
       "force_models[0].muscles[0].fibres.file: unknown key 'file'"},
      {"region with two forms",
       replaced(s, "{elements: [30, 31, 32]}", "{elements: [30], box: {min: [0, 0, 0], max: [1, 1, 1]}}"), 17,
       "force_models[0].muscles[1].region: expected one of 'box' or 'elements'"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_muscles.yaml");
}

}  // namespace
}  // namespace tt
