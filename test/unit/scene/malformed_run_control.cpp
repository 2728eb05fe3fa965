// Bad stop conditions in a scene's `run` map: one error line naming the file, the line and
// the key. (Built again under AddressSanitizer + UBSan by scripts/test.)
#include <gtest/gtest.h>

#include <string>

#include "scene_test_util.h"

namespace tt {
namespace {

const char* const kRunControlScene = R"(mesh: {generator: box, nodes: [2, 2, 2], size: [0.01, 0.01, 0.01]}
materials: [{young_modulus: 3000, poisson_ratio: 0.4}]
force_models: [{type: tensor_mass}]
integrator: {type: backward_euler}
run: RUN
)";

std::string withRun(const std::string& run) { return testutil::replaced(kRunControlScene, "RUN", run); }

TEST(MalformedRunControl, EachBadStopConditionFailsWithOneLine) {
  testutil::expectEachSceneFailsClearly(
      {
          {"misspelt stop key", withRun("{stop_kinetic_enery: 1e-6}"), 5,
           "unknown key 'stop_kinetic_enery'"},
          {"zero threshold", withRun("{stop_kinetic_energy: 0}"), 5,
           "run.stop_kinetic_energy: expected a positive number"},
          {"negative threshold", withRun("{stop_kinetic_energy: -1e-6}"), 5,
           "run.stop_kinetic_energy: expected a positive number"},
          {"threshold not a number", withRun("{stop_kinetic_energy: low}"), 5,
           "run.stop_kinetic_energy"},
          {"start time without a threshold", withRun("{stop_not_before: 0.1}"), 5,
           "run.stop_not_before: applies only together with stop_kinetic_energy"},
          {"negative start time", withRun("{stop_kinetic_energy: 1e-6, stop_not_before: -0.1}"), 5,
           "run.stop_not_before: expected a time >= 0"},
          {"start time a list", withRun("{stop_kinetic_energy: 1e-6, stop_not_before: [1]}"), 5,
           "run.stop_not_before"},
          {"longest frame below the frame", withRun("{frame_time: 0.01, max_frame_time: 0.005}"), 5,
           "run.max_frame_time: expected a time >= run.frame_time (0.01 s), got 0.005"},
          {"longest frame negative", withRun("{max_frame_time: -1}"), 5,
           "run.max_frame_time: expected a time >= run.frame_time (0.01 s), got -1"},
          {"longest frame not a number", withRun("{max_frame_time: long}"), 5,
           "run.max_frame_time: expected a finite number"},
          {"longest frame infinite", withRun("{max_frame_time: .inf}"), 5,
           "run.max_frame_time: expected a finite number"},
          {"negative settle time", withRun("{settle_time: -0.5}"), 5,
           "run.settle_time: expected a simulated time >= 0 (s)"},
          {"settle time not a number", withRun("{settle_time: long}"), 5,
           "run.settle_time: expected a finite number"},
      },
      "bad_run.yaml");
}

}  // namespace
}  // namespace tt
