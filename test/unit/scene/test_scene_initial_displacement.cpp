// Initial displacement, "Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.5.1, Eq.
// 2.124: the state at t = 0 may differ from the initialised one, u_init = u^0 + Delta u, while
// the passive forces F_d(u, u_init) keep the initialised (rest) state as their reference.
// loads.initial_displacement gives d = u^0 - u_init = -Delta u for every particle, the
// boundary's constrained DOFs excepted.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "scene_test_util.h"
#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/scene/scene_runner.h"

namespace tt {
namespace {

const char* const kDisplacedBlock = R"(mesh: {generator: box, nodes: [3, 3, 3], size: [0.02, 0.02, 0.03]}
materials: [{young_modulus: 5000, poisson_ratio: 0.3, density: 1000}]
force_models: [{type: hyperelastic, law: neo_hookean}]
integrator: {type: backward_euler, background_refactor: false}
loads: {initial_displacement: [0.001, 0, -0.0005]DAMPING}
BOUNDARY
run: {frame_time: 0.01, duration: 1.0}
)";

const Eigen::Vector3d kDisplacement(0.001, 0, -0.0005);

Scene displaced(const std::string& boundary, const std::string& damping = "") {
  return loadScene(testutil::writeScene(
      "displaced.yaml", testutil::replaced(testutil::replaced(kDisplacedBlock, "BOUNDARY", boundary),
                                           "DAMPING", damping)));
}

const char* const kHeldBottom = "boundary: {fixed: [{plane: {point: [0, 0, 0], normal: [0, 0, 1]}}]}";

bool onBottom(const System& s, int n) { return s.mesh.rest(2, n) < 1e-12; }

// Every particle starts at rest + d but the held ones, which stay where the boundary holds them.
TEST(InitialDisplacement, FreeParticlesStartDisplacedTheHeldOnesAtRest) {
  Scene s = displaced(kHeldBottom);
  int held = 0;
  for (int n = 0; n < s.system.numNodes(); ++n) {
    const Eigen::Vector3d expected =
        s.system.mesh.rest.col(n) + (onBottom(s.system, n) ? Eigen::Vector3d::Zero() : kDisplacement);
    held += onBottom(s.system, n);
    EXPECT_EQ(s.system.state.x.segment<3>(3 * n), expected) << n;
    EXPECT_EQ(s.system.state.v.segment<3>(3 * n), Eigen::Vector3d::Zero()) << n;
  }
  EXPECT_EQ(held, 9);
}

// The rest state stays the forces' reference: a free block displaced as a whole is a rigid
// translation (no force, no energy) and stays where it starts.
TEST(InitialDisplacement, AFreeBlockDisplacedAsAWholeFeelsNoForce) {
  Scene s = displaced("");
  Eigen::VectorXd f;
  const double energy = s.system.computeForce(s.system.state.x, s.system.state.v, f);
  EXPECT_NEAR(energy, 0.0, 1e-15);
  EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-12);
  const Eigen::VectorXd x0 = s.system.state.x;
  for (int frame = 0; frame < 5; ++frame) ASSERT_TRUE(s.integrator->advance(s.system, 0.01).ok);
  EXPECT_LT((s.system.state.x - x0).cwiseAbs().maxCoeff(), 1e-12);
}

// Held at its bottom, the displaced block is strained at t = 0: the force on the free nodes
// points back along -d, and with damping the block returns to its rest (initialised) state,
// not to the displaced start.
TEST(InitialDisplacement, AHeldBlockReturnsToItsInitialisedState) {
  Scene s = displaced(kHeldBottom, ", rayleigh_mass: 30");
  Eigen::VectorXd f;
  EXPECT_GT(s.system.computeForce(s.system.state.x, s.system.state.v, f), 0.0);
  Eigen::Vector3d resultant = Eigen::Vector3d::Zero();
  for (int n = 0; n < s.system.numNodes(); ++n)
    if (!onBottom(s.system, n)) resultant += f.segment<3>(3 * n);
  EXPECT_LT(resultant.dot(kDisplacement), 0.0);
  const RunSummary run = runScene(s, {});
  ASSERT_TRUE(run.ok) << run.failure;
  double largest = 0.0;
  for (int n = 0; n < s.system.numNodes(); ++n)
    largest = std::max(largest, (s.system.state.x.segment<3>(3 * n) - s.system.mesh.rest.col(n)).norm());
  EXPECT_LT(largest, 1e-3 * kDisplacement.norm());
}

}  // namespace
}  // namespace tt
