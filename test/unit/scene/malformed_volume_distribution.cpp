// Bad `distribution` keys of the virtual hexahedron (the volume law's point forces along the
// axes or to the vertices): one error line naming the file, the line and the key.
// (Built again under AddressSanitizer + UBSan by scripts/test.)
#include <gtest/gtest.h>

#include <string>

#include "scene_test_util.h"

namespace tt {
namespace {

const char* const kVolumeScene = R"(mesh: {generator: box, nodes: [2, 2, 2], size: [0.01, 0.01, 0.01]}
materials: [{young_modulus: 3000, poisson_ratio: 0.4, volume_stiffness: 100}]
force_models: [{type: virtual_hexahedron, law: LAW}]
integrator: {type: backward_euler}
)";

TEST(MalformedVolumeDistribution, EachBadDistributionFailsWithOneLine) {
  const auto with = [](const std::string& law) {
    return testutil::replaced(kVolumeScene, "LAW", law);
  };
  testutil::expectEachSceneFailsClearly(
      {
          {"unknown distribution", with("volume, distribution: vertex"), 3,
           "force_models[0].distribution"},
          {"distribution not a word", with("volume, distribution: [axes]"), 3,
           "force_models[0].distribution"},
          {"distribution of another law", with("stvk, distribution: vertices"), 3,
           "force_models[0].distribution: applies to law: volume only"},
          {"misspelt key", with("volume, distribusion: axes"), 3, "distribusion"},
      },
      "bad_distribution.yaml");
}

}  // namespace
}  // namespace tt
