// Bad adamss_active_tension entries: each gives one InputError naming the file, the line and
// the key. (Built again under AddressSanitizer + UBSan by scripts/test.)
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_util.h"

namespace tt {
namespace {

// Line numbers below refer to this text.
const char* const kScene = R"(name: active_box
mesh: {generator: box, nodes: [3, 2, 2], size: [0.02, 0.01, 0.01], split: none}
materials:
  - {young_modulus: 30, poisson_ratio: 0.3, stress_unit: kPa}
force_models:
  - type: adamss_active_tension
    form: anisotropic
    mode: tension
    stress_unit: kPa
    curve:
      type: piecewise_linear
      times: [0, 0.1, 0.2]
      values: [0, 2, 0]
integrator: {type: symplectic_euler, time_step: 1e-5}
)";

using testutil::BadScene;
using testutil::replaced;

TEST(MalformedActiveTensionScene, GoodSceneLoads) {
  EXPECT_NO_THROW(loadScene(testutil::writeScene("active_good.yaml", kScene)));
}

TEST(MalformedActiveTensionScene, EachErrorNamesFileLineAndKey) {
  const std::string s = kScene;
  const std::vector<BadScene> cases = {
      {"unknown form", replaced(s, "form: anisotropic", "form: fibre"), 7,
       "force_models[0].form: expected one of: anisotropic, isotropic; got 'fibre'"},
      {"unknown mode", replaced(s, "mode: tension", "mode: stress"), 8,
       "force_models[0].mode: expected one of: tension, force; got 'stress'"},
      {"unknown unit", replaced(s, "stress_unit: kPa\n    curve", "stress_unit: psi\n    curve"), 9,
       "force_models[0].stress_unit: expected one of: Pa, kPa, MPa"},
      {"misspelt key", replaced(s, "    mode: tension", "    mod: tension"), 8,
       "force_models[0].mod: unknown key 'mod'"},
      {"no curve",
       replaced(s, "    curve:\n      type: piecewise_linear\n      times: [0, 0.1, 0.2]\n      values: [0, 2, 0]\n", ""),
       6, "force_models[0]: missing required key 'curve'"},
      {"curve as a number",
       replaced(s, "    curve:\n      type: piecewise_linear\n      times: [0, 0.1, 0.2]\n      values: [0, 2, 0]\n",
                "    curve: 2\n"),
       10, "force_models[0].curve: expected a curve map"},
      {"unknown curve type", replaced(s, "type: piecewise_linear", "type: step"), 11,
       "force_models[0].curve.type: expected one of: constant, piecewise_linear, twitch; got 'step'"},
      {"times not increasing", replaced(s, "times: [0, 0.1, 0.2]", "times: [0, 0.2, 0.1]"), 12,
       "force_models[0].curve.times[2]: expected strictly increasing times, got 0.1 after 0.2"},
      {"a value missing", replaced(s, "values: [0, 2, 0]", "values: [0, 2]"), 13,
       "force_models[0].curve.values: expected 3 values (one per time), got 2"},
      {"a key of another curve type", replaced(s, "values: [0, 2, 0]", "values: [0, 2, 0]\n      peak: 3"), 14,
       "force_models[0].curve.peak: unknown key 'peak'"},
      {"twitch longer than its period",
       replaced(s, "      type: piecewise_linear\n      times: [0, 0.1, 0.2]\n      values: [0, 2, 0]\n",
                "      type: twitch\n      period: 0.5\n      peak: 2\n      rise_time: 0.2\n      decay_time: 0.4\n"),
       15, "force_models[0].curve.decay_time: expected rise_time + decay_time <= period (0.5), got 0.2 + 0.4"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_active_tension.yaml");
}

}  // namespace
}  // namespace tt
