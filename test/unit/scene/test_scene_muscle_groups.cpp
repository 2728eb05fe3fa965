// muscle_groups in a scene: two muscles of one block with crossed fibres, each contracting its
// own layer along its own fibre in a quasistatic solve; activations set from outside through
// System::findActivation and from a time curve.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "scene_test_util.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

const char* const kTwoMuscles = R"(name: two_muscles
mesh: {generator: box, nodes: [5, 5, 3], size: [0.02, 0.02, 0.01]}
materials:
  - young_modulus: 20
    poisson_ratio: 0.45
    stress_unit: kPa
    teran_muscle: {mooney_rivlin: [6, 2], bulk: 60, peak_stress: 4}
force_models:
  - type: muscle_groups
    law: teran_muscle
    muscles:
      - name: lower
        region: {box: {min: [-1, -1, -1], max: [1, 1, 0.005]}}
        fibres: {direction: [1, 0, 0]}
        activation: 0.5
      - name: upper
        region: {box: {min: [-1, -1, 0.005], max: [1, 1, 1]}}
        fibres: {direction: [0, 1, 0]}
integrator: {type: quasistatic, newton_abs_tolerance: 1e-10}
boundary:
  fixed:
    - {box: {min: [-0.001, -0.001, -0.001], max: [0.001, 0.001, 0.001]}}
    - {box: {min: [0.019, -0.001, -0.001], max: [0.021, 0.001, 0.001]}, axes: yz}
    - {box: {min: [-0.001, 0.019, -0.001], max: [0.001, 0.021, 0.001]}, axes: z}
run: {frame_time: 1, duration: 1}
)";

// The extent along `axis` of the nodes whose rest z is `z`.
double extent(const System& s, int axis, double z) {
  double lo = 1e9, hi = -1e9;
  for (int n = 0; n < s.numNodes(); ++n)
    if (std::abs(s.mesh.rest(2, n) - z) < 1e-9) {
      lo = std::min(lo, s.state.x[3 * n + axis]);
      hi = std::max(hi, s.state.x[3 * n + axis]);
    }
  return hi - lo;
}

TEST(MuscleGroupsScene, EachMuscleContractsItsLayerAlongItsFibre) {
  Scene scene = loadScene(testutil::writeScene("two_muscles.yaml", kTwoMuscles));
  System& s = scene.system;
  const ActivationRef lower = s.findActivation("lower"), upper = s.findActivation("upper");
  ASSERT_NE(lower.model, nullptr);
  ASSERT_NE(upper.model, nullptr);
  EXPECT_EQ(s.findActivation("middle").model, nullptr);
  EXPECT_EQ(lower.model->activation(lower.index), 0.5);
  EXPECT_EQ(upper.model->activation(upper.index), 0.0);

  StepReport r = scene.integrator->advance(s, scene.frameTime);
  ASSERT_TRUE(r.ok) << r.failure;
  const double bottomX = extent(s, 0, 0.0), bottomY = extent(s, 1, 0.0);
  std::printf("lower active: bottom %.5f x %.5f m, top %.5f x %.5f m (rest 0.02)\n", bottomX,
              bottomY, extent(s, 0, 0.01), extent(s, 1, 0.01));
  EXPECT_LT(bottomX, 0.02 * 0.98);   // shortened along its fibre x
  EXPECT_GT(bottomY, 0.02);          // and widened across it (isochoric)

  lower.model->setActivation(lower.index, 0.0);
  upper.model->setActivation(upper.index, 0.5);
  r = scene.integrator->advance(s, scene.frameTime);
  ASSERT_TRUE(r.ok) << r.failure;
  const double topX = extent(s, 0, 0.01), topY = extent(s, 1, 0.01);
  std::printf("upper active: bottom %.5f x %.5f m, top %.5f x %.5f m\n", extent(s, 0, 0.0),
              extent(s, 1, 0.0), topX, topY);
  EXPECT_LT(topY, 0.02 * 0.98);
  EXPECT_GT(topX, 0.02);
  // The block's mirror (z -> 0.01 - z, x <-> y) maps one case onto the other.
  EXPECT_NEAR(topY, bottomX, 1e-3 * (0.02 - bottomX));
  EXPECT_NEAR(topX, bottomY, 1e-3 * (bottomY - 0.02));
}

TEST(MuscleGroupsScene, ActivationFollowsItsTimeCurve) {
  Scene scene = loadScene(testutil::writeScene(
      "muscle_curve.yaml",
      testutil::replaced(kTwoMuscles, "activation: 0.5",
                         "activation: {type: piecewise_linear, times: [0, 2], values: [0, 0.4]}")));
  System& s = scene.system;
  const ActivationRef lower = s.findActivation("lower");
  ASSERT_NE(lower.model, nullptr);
  EXPECT_EQ(lower.model->activation(lower.index), 0.0);
  const StepReport r = scene.integrator->advance(s, scene.frameTime);
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_NEAR(lower.model->activation(lower.index), 0.2, 1e-15);  // the frame's end, t = 1
  EXPECT_LT(extent(s, 0, 0.0), 0.02);
}

// config/scenes/tongue_muscles.yaml loads, with its three muscles reachable by name, the
// palate's collision model, and the root (every constrained node) attached to the jaw.
TEST(MuscleGroupsScene, TongueSceneLoads) {
  Scene scene = loadScene(std::string(TT_SOURCE_DIR) + "/config/scenes/tongue_muscles.yaml");
  const System& s = scene.system;
  for (const char* name : {"superior_longitudinal", "transverse", "genioglossus"})
    EXPECT_NE(s.findActivation(name).model, nullptr) << name;
  std::vector<int> root;
  for (int n = 0; n < s.numNodes(); ++n)
    if (s.isConstrained[3 * n]) root.push_back(n);
  EXPECT_FALSE(root.empty());
  EXPECT_EQ(scene.jawNodes, root);
  ASSERT_EQ(s.models.size(), 3u);  // muscles, collision, gravity
  EXPECT_STREQ(s.models[1]->name(), "collision");
  const Eigen::VectorXd rest = Eigen::Map<const Eigen::VectorXd>(s.mesh.rest.data(), s.numDofs());
  Eigen::VectorXd f = Eigen::VectorXd::Zero(s.numDofs());
  s.models[0]->addForce(rest, rest, f);
  EXPECT_LT(f.lpNorm<Eigen::Infinity>(), 1e-9);  // at rest, no activation at t = 0: no force
}

}  // namespace
}  // namespace tt
