// The stability guard on a hex mesh: a step that pushes a node of a hex through the opposite
// face leaves a hex that is no longer a simple polyhedron ("Adamss: Advanced Anisotropic
// Mass-Spring System", Sec. 2.9.1, Fig. 2.30); the guard rejects it, naming the hex, and
// recovers with shorter steps, after which no element is corrupt.
#include <gtest/gtest.h>

#include <string>

#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/mesh/corrupt_elements.h"
#include "tissue_trainer/core/scene/scene.h"
#include "../scene/scene_test_util.h"

namespace tt {
namespace {

constexpr double kHexFrame = 1e-3;  // s, one explicit step per frame

// One 1 cm StVK hex (E = 100 MPa), every node fixed but the corner (1, 1, 1) cm, which starts
// moving down at 15 m/s: one step of a frame takes it 1.5 cm down, through the bottom face;
// the material stops it within about 0.2 mm when the steps are short enough to be stable.
Scene hexScene(int maxHalvings) {
  const std::string text = R"(mesh: {generator: box, nodes: [2, 2, 2], size: [0.01, 0.01, 0.01], split: none}
materials: [{young_modulus: 100, stress_unit: MPa, poisson_ratio: 0.3}]
force_models: [{type: hyperelastic, law: stvk}]
integrator: {type: symplectic_euler, time_step: 0.001}
stability_guard: {max_halvings: HALVINGS}
)";
  Scene scene = loadScene(testutil::writeScene(
      "guard_hex.yaml", testutil::replaced(text, "HALVINGS", std::to_string(maxHalvings))));
  System& s = scene.system;
  for (int n = 0; n < s.numNodes(); ++n)
    if ((s.mesh.rest.col(n) - Eigen::Vector3d::Constant(0.01)).norm() > 1e-12)
      s.mesh.nodeTags[n] = kFixedAll;
  s.updateConstraints();
  return scene;
}

int movingNode(const System& s) {
  for (int n = 0; n < s.numNodes(); ++n)
    if (s.mesh.nodeTags[n] == 0) return n;
  return -1;
}

TEST(StabilityGuardHex, RejectsAStepThatCorruptsAHexNamingIt) {
  Scene scene = hexScene(0);
  System& s = scene.system;
  const int node = movingNode(s);
  ASSERT_GE(node, 0);
  s.state.v[3 * node + 2] = -15.0;
  const State before = s.state;
  const StepReport r = scene.integrator->advance(s, kHexFrame);
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("hex 0 (tet "), std::string::npos) << r.failure;
  EXPECT_NE(r.failure.find("-tet split) inverted or flat"), std::string::npos) << r.failure;
  EXPECT_EQ(s.state.x, before.x);
  // Unguarded, the same step does corrupt the hex.
  unguarded(*scene.integrator).advance(s, kHexFrame);
  const Eigen::Map<const Eigen::Matrix3Xd> x(s.state.x.data(), 3, s.numNodes());
  EXPECT_FALSE(corruptElements(s.mesh, x).empty());
}

TEST(StabilityGuardHex, RecoversWithShorterSteps) {
  Scene scene = hexScene(10);
  System& s = scene.system;
  const int node = movingNode(s);
  s.state.v[3 * node + 2] = -15.0;
  for (int frame = 0; frame < 3; ++frame) {
    const StepReport r = scene.integrator->advance(s, kHexFrame);
    ASSERT_TRUE(r.ok) << r.failure;
    if (frame == 0) EXPECT_GT(guardOf(*scene.integrator)->lastFrame().halvings, 0);
    const Eigen::Map<const Eigen::Matrix3Xd> x(s.state.x.data(), 3, s.numNodes());
    EXPECT_TRUE(corruptElements(s.mesh, x).empty()) << "frame " << frame;
    // Stopped well before the bottom face.
    EXPECT_GT(s.state.x[3 * node + 2], 0.005) << "frame " << frame;
  }
}

}  // namespace
}  // namespace tt
