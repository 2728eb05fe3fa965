// A material whose law's constants are missing: one InputError naming the file, the line of
// the materials entry, the missing key and what was expected (never a default).
// (Built again under AddressSanitizer + UBSan by scripts/test.)
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_util.h"

namespace tt {
namespace {

using testutil::BadScene;
using testutil::replaced;

// Line numbers below refer to this text (the materials entry starts on line 4).
const char* const kStvkScene = R"(name: stvk_block
mesh: {generator: box, nodes: [3, 3, 3], size: [0.01, 0.01, 0.01]}
materials:
  - young_modulus: 20
    poisson_ratio: 0.3
    stress_unit: kPa
force_models:
  - {type: hyperelastic, law: stvk}
integrator: {type: backward_euler}
)";

std::string withModel(const std::string& model) {
  return replaced(kStvkScene, "{type: hyperelastic, law: stvk}", model);
}

TEST(MalformedMaterialConstants, GoodSceneLoads) {
  EXPECT_NO_THROW(loadScene(testutil::writeScene("stvk_good.yaml", kStvkScene)));
}

TEST(MalformedMaterialConstants, MissingConstantNamesTheKey) {
  const std::string noPoisson = replaced(kStvkScene, "    poisson_ratio: 0.3\n", "");
  const std::string noModulus = replaced(kStvkScene, "  - young_modulus: 20\n    poisson_ratio",
                                         "  - poisson_ratio");
  const std::string neither =
      replaced(kStvkScene, "  - young_modulus: 20\n    poisson_ratio: 0.3\n    stress_unit",
               "  - stress_unit");
  const std::string lambdaOnly =
      replaced(kStvkScene, "  - young_modulus: 20\n    poisson_ratio: 0.3\n", "  - lambda: 10\n");
  const std::vector<BadScene> cases = {
      {"stvk without poisson_ratio", noPoisson, 4,
       "materials[0]: missing poisson_ratio, which stvk reads beside young_modulus: expected a "
       "Poisson ratio in (-1, 0.5)"},
      {"stvk without young_modulus", noModulus, 4,
       "materials[0]: missing young_modulus, which stvk reads beside poisson_ratio"},
      {"stvk without any Lame constant", neither, 4,
       "materials[0]: missing young_modulus and poisson_ratio (or lambda and mu), which stvk "
       "reads"},
      {"lambda without mu", lambdaOnly, 4, "missing mu, which stvk reads beside lambda"},
      {"neo_hookean without poisson_ratio",
       replaced(withModel("{type: hyperelastic, law: neo_hookean}"), "    poisson_ratio: 0.3\n",
                ""),
       4, "missing poisson_ratio, which neo_hookean reads"},
      {"edge_length without poisson_ratio",
       replaced(withModel("{type: edge_length}"), "    poisson_ratio: 0.3\n", ""), 4,
       "missing poisson_ratio, which edge_length reads"},
      {"tensor_mass without constants",
       replaced(withModel("{type: tensor_mass}"),
                "  - young_modulus: 20\n    poisson_ratio: 0.3\n    stress_unit", "  - stress_unit"),
       4, "which tensor_mass reads"},
      {"volume without volume_stiffness",
       replaced(withModel("{type: hyperelastic, law: volume}"), "    stress_unit: kPa\n", ""), 4,
       "missing volume_stiffness, which volume reads: expected the stiffness p > 0"},
      {"longitudinal pair of the other form",
       replaced(kStvkScene, "    stress_unit", "    lambda_longitudinal: 5\n    stress_unit"), 6,
       "lambda_longitudinal goes with lambda/mu"},
  };
  testutil::expectEachSceneFailsClearly(cases, "material_constants.yaml");
}

}  // namespace
}  // namespace tt
