// Malformed loads.initial_velocity and loads.initial_displacement: one error line naming the file, line and key.
#include <gtest/gtest.h>

#include "scene_test_util.h"

namespace tt {
namespace {

const char* const kBlock = R"(mesh: {generator: box, nodes: [3, 3, 3], size: [0.02, 0.02, 0.03]}
materials: [{young_modulus: 5000, poisson_ratio: 0.3, density: 1000}]
force_models: [{type: hyperelastic, law: neo_hookean}]
integrator: {type: backward_euler}
LOADS
)";

std::string scene(const std::string& loads) { return testutil::replaced(kBlock, "LOADS", loads); }

TEST(MalformedInitialVelocity, OneLineNamingTheKey) {
  testutil::expectEachSceneFailsClearly(
      {{"two numbers", scene("loads: {initial_velocity: [0, 1]}"), 5,
        "loads.initial_velocity: expected a list of 3 numbers"},
       {"not a number", scene("loads: {initial_velocity: [0, fast, 0]}"), 5,
        "loads.initial_velocity[1]"},
       {"misspelt", scene("loads: {initial_velocity: [0, 0, 0], inital_velocity: [0, 0, 1]}"), 5,
        "loads.inital_velocity: unknown key"},
       {"displacement, two numbers", scene("loads: {initial_displacement: [0, 1]}"), 5,
        "loads.initial_displacement: expected a list of 3 numbers"},
       {"displacement, not a number", scene("loads: {initial_displacement: [0, far, 0]}"), 5,
        "loads.initial_displacement[1]"}},
      "bad_initial_velocity.yaml");
}

}  // namespace
}  // namespace tt
