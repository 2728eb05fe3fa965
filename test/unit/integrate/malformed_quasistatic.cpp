// The quasistatic integrator's scene keys: each malformed one is one InputError line naming
// the file, the line and the key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../scene/scene_test_util.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

// Line numbers below refer to this text.
const char* const kScene = R"(name: block
mesh: {generator: box, nodes: [2, 2, 2], size: [0.01, 0.01, 0.01]}
materials:
  - {young_modulus: 10, poisson_ratio: 0.3, stress_unit: kPa}
force_models:
  - {type: hyperelastic, law: neo_hookean}
integrator:
  type: quasistatic
  newton_abs_tolerance: 1e-8
  newton_tolerance: 1e-10
  max_newton_iterations: 20
  linear_tolerance: 1e-9
  linear_max_iterations: 300
  max_line_search: 12
  preconditioner: cholesky
  refactor_above: 7
  max_pseudo_time_steps: 40
)";

using testutil::replaced;

TEST(QuasistaticScene, KeysReachTheSolver) {
  Scene scene = loadScene(testutil::writeScene("quasistatic_keys.yaml",
                                               std::string(kScene) +
                                                   "stability_guard: {enabled: false}\n"));
  const auto* integrator = dynamic_cast<const QuasistaticIntegrator*>(scene.integrator.get());
  ASSERT_NE(integrator, nullptr);
  const EquilibriumParams& p = integrator->params();
  EXPECT_EQ(p.absoluteTolerance, 1e-8);
  EXPECT_EQ(p.relativeTolerance, 1e-10);
  EXPECT_EQ(p.maxNewtonIterations, 20);
  EXPECT_EQ(p.linearTolerance, 1e-9);
  EXPECT_EQ(p.linearMaxIterations, 300);
  EXPECT_EQ(p.maxLineSearchSteps, 12);
  EXPECT_EQ(p.preconditioner, EquilibriumParams::Preconditioning::kCholesky);
  EXPECT_EQ(p.refactorIterations, 7);
  EXPECT_EQ(p.maxPseudoTimeSteps, 40);
}

TEST(QuasistaticScene, EachMalformedKeyNamesFileLineAndKey) {
  const std::string s = kScene;
  const std::vector<testutil::BadScene> cases = {
      {"negative tolerance",
       replaced(s, "newton_abs_tolerance: 1e-8", "newton_abs_tolerance: -1"), 9,
       "integrator.newton_abs_tolerance"},
      {"zero relative tolerance", replaced(s, "newton_tolerance: 1e-10", "newton_tolerance: 0"),
       10, "integrator.newton_tolerance"},
      {"fractional iterations", replaced(s, "max_newton_iterations: 20", "max_newton_iterations: 2.5"),
       11, "integrator.max_newton_iterations"},
      {"zero iterations", replaced(s, "max_newton_iterations: 20", "max_newton_iterations: 0"), 11,
       "integrator.max_newton_iterations"},
      {"text tolerance", replaced(s, "linear_tolerance: 1e-9", "linear_tolerance: tight"), 12,
       "integrator.linear_tolerance"},
      {"negative line search", replaced(s, "max_line_search: 12", "max_line_search: -1"), 14,
       "integrator.max_line_search"},
      {"unknown preconditioner", replaced(s, "preconditioner: cholesky", "preconditioner: ilu"), 15,
       "integrator.preconditioner"},
      {"negative refactor_above", replaced(s, "refactor_above: 7", "refactor_above: -1"), 16,
       "integrator.refactor_above"},
      {"fractional refactor_above", replaced(s, "refactor_above: 7", "refactor_above: 2.5"), 16,
       "integrator.refactor_above"},
      {"negative pseudo-time steps",
       replaced(s, "max_pseudo_time_steps: 40", "max_pseudo_time_steps: -3"), 17,
       "integrator.max_pseudo_time_steps"},
      {"fractional pseudo-time steps",
       replaced(s, "max_pseudo_time_steps: 40", "max_pseudo_time_steps: 1.5"), 17,
       "integrator.max_pseudo_time_steps"},
      {"misspelt pseudo-time key",
       replaced(s, "max_pseudo_time_steps: 40", "max_pseudotime_steps: 40"), 17,
       "max_pseudotime_steps"},
      {"misspelt key", replaced(s, "newton_abs_tolerance: 1e-8", "newton_abs_tolerence: 1e-8"), 9,
       "newton_abs_tolerence"},
      {"a key of another integrator", replaced(s, "max_line_search: 12", "substeps: 2"), 14,
       "substeps"},
  };
  testutil::expectEachSceneFailsClearly(cases, "quasistatic_bad.yaml");
}

}  // namespace
}  // namespace tt
