// collision in a scene: a block pushed down onto a plane by its controlled top face stops on
// the plane (quasistatic frames), within the penetration its contact forces need; an OBJ body
// and the node selections reach the model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>

#include "scene_test_util.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

const char* const kPressedBlock = R"(name: pressed_block
mesh: {generator: box, nodes: [3, 3, 3], size: [0.01, 0.01, 0.01]}
materials:
  - {young_modulus: 10, poisson_ratio: 0.3, stress_unit: kPa}
force_models:
  - {type: hyperelastic, law: neo_hookean}
  - type: collision
    stiffness: 1000
    bodies:
      - plane: {point: [0, 0, -0.001], normal: [0, 0, 1]}
integrator: {type: quasistatic, newton_abs_tolerance: 1e-10}
boundary:
  controlled:
    - plane: {point: [0, 0, 0.01], normal: [0, 0, 1]}
      path: [[0, 0, 0, 0], [1, 0, 0, -0.003]]
run: {frame_time: 0.25, duration: 1}
)";

TEST(CollisionScene, BlockPressedOntoAPlaneEndsOnIt) {
  Scene scene = loadScene(testutil::writeScene("pressed_block.yaml", kPressedBlock));
  System& s = scene.system;
  ASSERT_EQ(s.models.size(), 2u);
  for (int frame = 0; frame < 4; ++frame) {
    const StepReport r = scene.integrator->advance(s, scene.frameTime);
    ASSERT_TRUE(r.ok) << r.failure;
  }
  double lowest = 1.0, contactForce = 0.0;
  for (int n = 0; n < s.numNodes(); ++n) lowest = std::min(lowest, s.state.x[3 * n + 2]);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(s.numDofs());
  s.models[1]->addForce(s.state.x, s.state.v, f);
  for (int n = 0; n < s.numNodes(); ++n) contactForce += f[3 * n + 2];
  const double penetration = -0.001 - lowest;
  std::printf("lowest node %.6f m (plane -0.001), penetration %.3g m, contact force %.4g N\n",
              lowest, penetration, contactForce);
  // Without the plane the block would translate 2 mm through it; here it stops on it, each
  // node as deep as its share of the contact force needs (d = f / eps).
  EXPECT_GT(penetration, 0.0);
  EXPECT_LT(penetration, contactForce / 1000.0);
  EXPECT_LT(penetration, 0.05 * 0.002);
  EXPECT_GT(contactForce, 0.05);  // the block is squeezed: 1 mm of 1 cm at 10 kPa
}

TEST(CollisionScene, ObjBodyAndNodeSelectionsLoad) {
  const std::string dir = std::filesystem::path(testutil::writeScene("unused.yaml", "")).parent_path();
  std::ofstream(dir + "/unit_cube.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n"
                                           "v 1 1 1\nv 0 1 1\nf 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\n"
                                           "f 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\n"
                                           "f 2 3 7\nf 2 7 6\n";
  // The cube scaled to 4 mm and moved so that the block's corner node (0, 0, 0) is 1 mm inside.
  const std::string scene = testutil::replaced(
      kPressedBlock, "      - plane: {point: [0, 0, -0.001], normal: [0, 0, 1]}",
      "      - mesh: {file: unit_cube.obj, scale: 0.004, translate: [-0.003, -0.003, -0.003]}");
  for (const char* nodes : {"", "    nodes: all\n", "    nodes: surface\n",
                            "    nodes: {box: {min: [-1, -1, -1], max: [0.001, 0.001, 0.001]}}\n",
                            "    nodes: {region: {box: {min: [-1, -1, -1], max: [0.003, 0.003, 0.003]}}}\n"}) {
    Scene s = loadScene(testutil::writeScene(
        "obj_body.yaml", testutil::replaced(scene, "    stiffness: 1000\n",
                                            std::string("    stiffness: 1000\n") + nodes)));
    Eigen::VectorXd f = Eigen::VectorXd::Zero(s.system.numDofs());
    s.system.models[1]->addForce(s.system.state.x, s.system.state.v, f);
    // Node 0 is at the origin: 1 mm inside each of three faces, pushed out along one of them.
    int corner = -1;
    for (int n = 0; n < s.system.numNodes(); ++n)
      if (s.system.mesh.rest.col(n).norm() < 1e-12) corner = n;
    ASSERT_GE(corner, 0);
    EXPECT_NEAR(f.segment<3>(3 * corner).norm(), 1000.0 * 0.001, 1e-12) << nodes;
    EXPECT_NEAR(f.norm(), 1000.0 * 0.001, 1e-12) << nodes;  // no other node inside
  }
}

}  // namespace
}  // namespace tt
