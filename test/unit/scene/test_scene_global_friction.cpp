// Global friction, "Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.4.4.2, Eq. 2.118:
// f_i = -mu v_i on every particle, mu >= 0 in N s/m, not scaled by the mass. It is the scene
// key loads.node_damping (loads.rayleigh_mass is the mass-scaled f_i = -alpha m_i v_i). The
// damping goes on the diagonal of the implicit integrators' matrix.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "scene_test_util.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

// A free block (no boundary conditions, no gravity) with the friction of Eq. 2.118.
const char* const kFree = R"(mesh: {generator: box, nodes: [3, 3, 3], size: [0.02, 0.02, 0.03]}
materials: [{young_modulus: 5000, poisson_ratio: 0.3, density: 1000}]
force_models: [{type: tensor_mass}]
integrator: {type: backward_euler}
loads: {node_damping: 0.3}
run: {frame_time: 0.01, duration: 0.01}
)";

TEST(GlobalFriction, NodeDampingIsTheForceOfEq2118) {
  Scene scene = loadScene(testutil::writeScene("friction.yaml", kFree));
  const System& s = scene.system;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  Eigen::VectorXd v(3 * s.numNodes());
  for (Eigen::Index k = 0; k < v.size(); ++k) v[k] = u(rng);
  Eigen::VectorXd f;
  const Eigen::VectorXd rest = Eigen::Map<const Eigen::VectorXd>(s.mesh.rest.data(), v.size());
  scene.system.computeForce(rest, v, f);  // at rest: no elastic force
  for (Eigen::Index k = 0; k < v.size(); ++k) EXPECT_NEAR(f[k], -0.3 * v[k], 1e-15) << k;
}

// One backward Euler step from a uniform translation: the step's velocity v1 satisfies
// M (v1 - v0) = h f(x1, v1), the friction taken at v1, to the solver's tolerance. With a
// material soft enough that the elastic forces do not matter, that is v1 = v0 m / (m + h mu)
// per DOF (the explicit step would give v0 (1 - h mu / m), negative here).
TEST(GlobalFriction, BackwardEulerTreatsItImplicitly) {
  for (const char* modulus : {"5000", "1.0e-6"}) {
    SCOPED_TRACE(modulus);
    Scene scene = loadScene(testutil::writeScene(
        "friction.yaml", testutil::replaced(kFree, "young_modulus: 5000",
                                            std::string("young_modulus: ") + modulus)));
    System& s = scene.system;
    const Eigen::Vector3d v0(0.02, -0.01, 0.1);
    for (int i = 0; i < s.numNodes(); ++i) s.state.v.segment<3>(3 * i) = v0;
    const Eigen::VectorXd start = s.state.v;
    const double h = scene.frameTime, mu = 0.3;
    EXPECT_GT(h * mu / s.mass.maxCoeff(), 1.0) << "the friction must dominate for the test to tell";
    ASSERT_TRUE(scene.integrator->advance(s, h).ok);
    Eigen::VectorXd f;
    s.computeForce(s.state.x, s.state.v, f);
    const Eigen::VectorXd residual = s.mass.cwiseProduct(s.state.v - start) - h * f;
    EXPECT_LT(residual.norm(), 1e-6 * (h * mu * start).norm());
    if (std::string(modulus) == "5000") continue;
    for (Eigen::Index k = 0; k < start.size(); ++k) {
      const double m = s.mass[k];
      EXPECT_NEAR(s.state.v[k], start[k] * m / (m + h * mu), 1e-9 * v0.norm()) << k;
    }
  }
}

}  // namespace
}  // namespace tt
