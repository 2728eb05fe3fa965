// External acceleration and initial velocity, "Adamss: Advanced Anisotropic Mass-Spring
// System", Secs. 2.4.4.1 and 2.4.4.4: loads.gravity is any uniform acceleration (f_i = m_i a,
// Eq. 2.117) and loads.initial_velocity gives every particle v0 at t = 0, the boundary's
// constrained DOFs excepted.
#include <gtest/gtest.h>

#include <string>

#include "scene_test_util.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

const char* const kVelocityBlock = R"(mesh: {generator: box, nodes: [3, 3, 3], size: [0.02, 0.02, 0.03]}
materials: [{young_modulus: 5000, poisson_ratio: 0.3, density: 1000}]
force_models: [{type: hyperelastic, law: neo_hookean}]
integrator: {type: backward_euler, substeps: 4}
LOADS
BOUNDARY
run: {frame_time: 0.01, duration: 0.1}
)";

Eigen::Vector3d centreOfMass(const System& s) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double mass = 0.0;
  for (int n = 0; n < s.numNodes(); ++n) {
    sum += s.mass[3 * n] * s.state.x.segment<3>(3 * n);
    mass += s.mass[3 * n];
  }
  return sum / mass;
}

std::string scene(const std::string& loads, const std::string& boundary = "") {
  return testutil::replaced(testutil::replaced(kVelocityBlock, "LOADS", loads), "BOUNDARY", boundary);
}

// A free block thrown with v0 and accelerated by a: its centre of mass follows
// c0 + v0 t + a t^2 / 2 (the internal forces sum to zero), to the Newton tolerance.
TEST(InitialVelocity, AFreeBlockFliesAlongV0WhileAccelerated) {
  Scene s = loadScene(testutil::writeScene(
      "thrown.yaml", scene("loads: {initial_velocity: [0.1, 0, -0.2], gravity: [0, 2, 0]}")));
  for (int n = 0; n < s.system.numNodes(); ++n)
    EXPECT_EQ(s.system.state.v.segment<3>(3 * n), Eigen::Vector3d(0.1, 0, -0.2)) << n;
  const Eigen::Vector3d c0 = centreOfMass(s.system);
  for (int frame = 0; frame < 10; ++frame) ASSERT_TRUE(s.integrator->advance(s.system, 0.01).ok);
  const double t = s.system.state.t;
  const Eigen::Vector3d expected = c0 + t * Eigen::Vector3d(0.1, 0, -0.2) +
                                   0.5 * t * t * Eigen::Vector3d(0, 2, 0);
  // Backward Euler integrates a constant acceleration with the error a h t / 2 (h = 2.5 ms).
  EXPECT_NEAR((centreOfMass(s.system) - expected).x(), 0.0, 1e-9);
  EXPECT_NEAR((centreOfMass(s.system) - expected).z(), 0.0, 1e-9);
  EXPECT_NEAR((centreOfMass(s.system) - expected).y(), 0.5 * 2 * 0.0025 * t, 1e-9);
}

// Fixed DOFs keep zero velocity, the free ones start with v0.
TEST(InitialVelocity, TheBoundaryKeepsItsOwnVelocities) {
  Scene s = loadScene(testutil::writeScene(
      "held.yaml", scene("loads: {initial_velocity: [0, 0, 0.1]}",
                         "boundary: {fixed: [{plane: {point: [0, 0, 0], normal: [0, 0, 1]}}]}")));
  int fixed = 0;
  for (int n = 0; n < s.system.numNodes(); ++n) {
    const bool onBottom = s.system.mesh.rest(2, n) < 1e-12;
    fixed += onBottom;
    EXPECT_EQ(s.system.state.v.segment<3>(3 * n),
              onBottom ? Eigen::Vector3d::Zero() : Eigen::Vector3d(0, 0, 0.1)) << n;
  }
  EXPECT_EQ(fixed, 9);
}

}  // namespace
}  // namespace tt
