// The Adamss spring models in a scene: the keys reach the models, and each malformed entry is
// one InputError naming the file, the line and the key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_util.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

// Line numbers below refer to this text.
const char* const kSpringScene = R"(name: spring_patch
mesh: {generator: box, nodes: [3, 3, 3], size: [0.01, 0.01, 0.01], split: none}
materials:
  - {young_modulus: 3000, poisson_ratio: 0.4}
force_models:
  - type: adamss_axial_springs
    area: true
    stress_unit: kPa
    stiffness: [[6.358, 0, 768], [0, 0, 288.525], [0.305, 0, 5.699]]
  - type: adamss_torsion_springs
    form: gradient
    stiffness: [[0.01], [0.01], [0.01]]
integrator: {type: symplectic_euler, time_step: 1e-5}
)";

using testutil::replaced;

TEST(AdamssSpringScene, KeysReachTheModels) {
  const Scene scene = loadScene(testutil::writeScene("springs.yaml", kSpringScene));
  ASSERT_EQ(scene.system.models.size(), 2u);
  EXPECT_STREQ(scene.system.models[0]->name(), "adamss_axial_springs");
  EXPECT_STREQ(scene.system.models[1]->name(), "adamss_torsion_springs");
  EXPECT_TRUE(scene.system.models[1]->hasEnergy());  // form: gradient
  // Stretch the box 10 % along x: the axial energy is, per element, A L0 sum k_i eps^(i+1)/(i+1)
  // with k in kPa, summing to V (k_1 eps^2 / 2 + k_3 eps^4 / 4) over the box's volume V.
  const Mesh& mesh = scene.system.mesh;
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(mesh.rest.data(), 3 * mesh.numNodes());
  for (int i = 0; i < x.size(); i += 3) x[i] *= 1.1;
  const double eps = 0.1, V = 1e-6;
  EXPECT_NEAR(scene.system.models[0]->energy(x), V * 1e3 * (6.358 * eps * eps / 2 + 768 * std::pow(eps, 4) / 4),
              1e-9 * V * 1e3);
}

// Friction has a velocity Jacobian and no position stiffness to add: backward Euler takes it.
TEST(AdamssSpringScene, FrictionRunsWithBackwardEuler) {
  const std::string text = replaced(
      replaced(kSpringScene, "  - type: adamss_torsion_springs\n    form: gradient\n    stiffness: [[0.01], [0.01], [0.01]]\n",
               "  - {type: adamss_axis_friction, coefficient: 0.5, form: virtual_hexahedron}\n"),
      "{type: symplectic_euler, time_step: 1e-5}", "{type: backward_euler}");
  const Scene scene = loadScene(testutil::writeScene("friction.yaml", text));
  ASSERT_EQ(scene.system.models.size(), 2u);
  EXPECT_TRUE(scene.system.models[1]->hasVelocityJacobian());
}

// The gradient torsion form has a stiffness: backward Euler takes the scene, and a frame from
// a sheared state (the torsion springs loaded) ends with the node positions finite and the
// top moved back towards rest.
TEST(AdamssSpringScene, GradientTorsionRunsWithBackwardEuler) {
  Scene scene = loadScene(testutil::writeScene(
      "torsion_implicit.yaml",
      replaced(kSpringScene, "{type: symplectic_euler, time_step: 1e-5}", "{type: backward_euler}")));
  System& s = scene.system;
  ASSERT_TRUE(s.models[1]->hasStiffness());
  for (int n = 0; n < s.numNodes(); ++n) s.state.x[3 * n] += 0.1 * s.mesh.rest(2, n);  // shear
  const double before = s.potentialEnergy(s.state.x);
  const StepReport r = scene.integrator->advance(s, 1e-3);
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_TRUE(s.state.x.allFinite());
  EXPECT_LT(s.potentialEnergy(s.state.x), before);
}

using testutil::BadScene;

TEST(AdamssSpringScene, EachMalformedEntryNamesFileLineAndKey) {
  const std::string s = kSpringScene;
  const std::string axial = "stiffness: [[6.358, 0, 768], [0, 0, 288.525], [0.305, 0, 5.699]]";
  const std::vector<BadScene> cases = {
      {"two lists", replaced(s, axial, "stiffness: [[1], [2]]"), 9,
       "force_models[0].stiffness: expected 3 lists of coefficients"},
      {"four orders", replaced(s, axial, "stiffness: [[1, 2, 3, 4], [2], [3]]"), 9,
       "force_models[0].stiffness[0]: expected 1 to 3 coefficients (orders 1, 2, 3), got 4"},
      {"a word", replaced(s, axial, "stiffness: [[1, stiff], [2], [3]]"), 9,
       "force_models[0].stiffness[0][1]: expected a finite number, got 'stiff'"},
      {"no stiffness", replaced(s, "    " + axial + "\n", ""), 6,
       "force_models[0]: missing required key 'stiffness'"},
      {"unit without area", replaced(s, "    area: true\n", ""), 7,
       "force_models[0].stress_unit: stress_unit applies to area: true only"},
      {"unknown unit", replaced(s, "stress_unit: kPa", "stress_unit: psi"), 8,
       "force_models[0].stress_unit"},
      {"unknown measure", replaced(s, "form: gradient", "measure: degrees"), 11,
       "force_models[1].measure: expected one of: angle, cosine"},
      {"unknown form", replaced(s, "form: gradient", "form: exact"), 11,
       "force_models[1].form: expected one of: printed, gradient"},
      {"unknown key", replaced(s, "form: gradient", "shape: gradient"), 11,
       "force_models[1].shape: unknown key"},
      {"printed torsion with an implicit integrator",
       replaced(replaced(s, "{type: symplectic_euler, time_step: 1e-5}", "{type: backward_euler}"),
                "form: gradient", "form: printed"), 13,
       "backward_euler needs the stiffness of every force model; adamss_torsion_springs provides none"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_springs.yaml");
  const std::string friction = replaced(
      s, "  - type: adamss_torsion_springs\n    form: gradient\n    stiffness: [[0.01], [0.01], [0.01]]\n",
      "  - {type: adamss_axis_friction, coefficient: 0.5}\n");
  const std::vector<BadScene> frictionCases = {
      {"negative coefficient", replaced(friction, "coefficient: 0.5", "coefficient: -1"), 10,
       "force_models[1].coefficient: expected a positive number"},
      {"unknown form", replaced(friction, "coefficient: 0.5", "coefficient: 0.5, form: viscous"), 10,
       "force_models[1].form: expected one of: bourguignon, area, virtual_hexahedron"},
      {"missing coefficient", replaced(friction, ", coefficient: 0.5", ""), 10,
       "force_models[1]: missing required key 'coefficient'"},
  };
  testutil::expectEachSceneFailsClearly(frictionCases, "bad_friction.yaml");
}

}  // namespace
}  // namespace tt
