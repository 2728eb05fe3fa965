// The backward_euler keys of the linear solver, the iteration-count step control and the
// finite-difference Jacobians: each reaches the integrator, each bad value or misplaced key
// gives one line naming the file, the line and the key; with finite differences a model
// without an analytic stiffness runs implicitly.
// (Built again under AddressSanitizer + UBSan by scripts/test.)
#include <gtest/gtest.h>

#include "scene_test_util.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

using testutil::BadScene;
using testutil::replaced;
using testutil::writeScene;

const char* const kBackwardEulerScene = R"(name: block
mesh:
  generator: box
  nodes: [3, 3, 3]
  size: [0.02, 0.02, 0.02]
materials:
  - young_modulus: 3
    stress_unit: kPa
    poisson_ratio: 0.4
force_models:
  - type: edge_length
integrator:
  type: backward_euler
  linear_tolerance: 1e-9
boundary:
  fixed:
    - plane: {point: [0, 0, 0], normal: [0, 0, 1]}
loads:
  gravity: [0, 0, -9.81]
stability_guard: {enabled: false}
run: {frame_time: 0.01, duration: 0.02}
)";

// The scene with `keys` (lines of "key: value") added to the integrator; they start on line 14.
std::string withKeys(const std::string& keys) {
  return replaced(kBackwardEulerScene, "  type: backward_euler\n", "  type: backward_euler\n" + keys);
}

const BackwardEulerIntegrator& integratorOf(const Scene& scene) {
  const auto* be = dynamic_cast<const BackwardEulerIntegrator*>(scene.integrator.get());
  EXPECT_NE(be, nullptr);
  return *be;
}

const BackwardEulerParams& paramsOf(const Scene& scene) { return integratorOf(scene).params; }

TEST(BackwardEulerKeys, ReachTheIntegrator) {
  using Params = BackwardEulerParams;
  const Scene plain = loadScene(writeScene("be_plain.yaml", kBackwardEulerScene));
  EXPECT_EQ(paramsOf(plain).linearSolver, Params::LinearSolver::kPcg);
  EXPECT_FALSE(paramsOf(plain).adaptive);
  EXPECT_EQ(paramsOf(plain).jacobian, Params::Jacobian::kAnalytic);

  const Scene scene = loadScene(writeScene(
      "be_keys.yaml",
      withKeys("  linear_solver: gmres\n  gmres_restart: 12\n  adaptive: true\n"
               "  lower_iterations: 3\n  upper_iterations: 25\n  initial_step: 2e-3\n"
               "  min_step: 1e-5\n  max_step: 5e-3\n  jacobian: finite_difference\n"
               "  coloring: false\n  fd_epsilon: 1e-7\n  fd_position_scale: 0.5\n"
               "  fd_velocity_scale: 2\n")));
  const Params& p = paramsOf(scene);
  EXPECT_EQ(p.linearSolver, Params::LinearSolver::kGmres);
  EXPECT_EQ(p.gmresRestart, 12);
  EXPECT_TRUE(p.adaptive);
  EXPECT_EQ(p.lowerIterations, 3);
  EXPECT_EQ(p.upperIterations, 25);
  EXPECT_EQ(p.initialStep, 2e-3);
  EXPECT_EQ(p.minStep, 1e-5);
  EXPECT_EQ(p.maxStep, 5e-3);
  EXPECT_EQ(p.jacobian, Params::Jacobian::kFiniteDifference);
  EXPECT_FALSE(p.finiteDifference.coloring);
  EXPECT_EQ(p.finiteDifference.epsilon, 1e-7);
  EXPECT_EQ(p.finiteDifference.positionScale, 0.5);
  EXPECT_EQ(p.finiteDifference.velocityScale, 2.0);
  EXPECT_STREQ(integratorOf(scene).stepControl().name(), "halving_doubling");

  const Scene bicg = loadScene(writeScene("be_bicg.yaml", withKeys("  linear_solver: bicgstab\n")));
  EXPECT_EQ(paramsOf(bicg).linearSolver, Params::LinearSolver::kBiCgStab);
  // Without initial_step the default first step is brought within the bounds.
  const Scene clamped = loadScene(
      writeScene("be_clamped.yaml", withKeys("  adaptive: true\n  min_step: 0.004\n")));
  EXPECT_EQ(paramsOf(clamped).initialStep, 0.004);
}

// The axis approximation of the virtual hexahedron has no analytic stiffness: refused with
// the analytic Jacobian, run with finite differences.
TEST(BackwardEulerKeys, FiniteDifferencesRunAModelWithoutStiffness) {
  const std::string approximation =
      replaced(kBackwardEulerScene, "  - type: edge_length\n",
               "  - type: virtual_hexahedron\n    law: stvk\n"
               "    deformation_gradient: axis_approximation\n");
  EXPECT_THROW(loadScene(writeScene("be_vh.yaml", approximation)), InputError);
  Scene scene = loadScene(writeScene(
      "be_vh_fd.yaml", replaced(approximation, "  linear_tolerance: 1e-9\n",
                                "  linear_tolerance: 1e-9\n  jacobian: finite_difference\n")));
  ASSERT_FALSE(scene.system.hasStiffness());
  const Eigen::VectorXd start = scene.system.state.x;
  for (int frame = 0; frame < 2; ++frame) {
    const StepReport r = scene.integrator->advance(scene.system, scene.frameTime);
    ASSERT_TRUE(r.ok) << r.failure;
  }
  EXPECT_TRUE(scene.system.state.x.allFinite());
  EXPECT_GT((scene.system.state.x - start).norm(), 0.0);  // gravity moved it
}

TEST(BackwardEulerKeys, EachBadKeyNamesFileLineAndKey) {
  const std::vector<BadScene> cases = {
      {"unknown solver", withKeys("  linear_solver: cg\n"), 14,
       "integrator.linear_solver: expected one of: pcg, gmres, bicgstab; got 'cg'"},
      {"restart without gmres", withKeys("  gmres_restart: 10\n"), 14,
       "integrator.gmres_restart: applies only with linear_solver: gmres"},
      {"zero restart", withKeys("  linear_solver: gmres\n  gmres_restart: 0\n"), 15,
       "integrator.gmres_restart: expected an integer >= 1"},
      {"step-control key without adaptive", withKeys("  upper_iterations: 30\n"), 14,
       "integrator.upper_iterations: applies only with adaptive: true"},
      {"substeps with adaptive", withKeys("  substeps: 2\n  adaptive: true\n"), 14,
       "integrator.substeps: does not apply with adaptive: true"},
      {"adaptive not a boolean", withKeys("  adaptive: sometimes\n"), 14,
       "integrator.adaptive: expected true or false"},
      {"limits in the wrong order",
       withKeys("  adaptive: true\n  lower_iterations: 20\n  upper_iterations: 20\n"), 16,
       "integrator.upper_iterations: expected upper_iterations (20) > lower_iterations (20)"},
      {"lower above the default upper", withKeys("  adaptive: true\n  lower_iterations: 50\n"), 15,
       "integrator.lower_iterations: expected upper_iterations (40) > lower_iterations (50)"},
      {"upper beyond the iteration limit",
       withKeys("  linear_max_iterations: 30\n  adaptive: true\n"), 14,
       "integrator.linear_max_iterations: expected upper_iterations (40) <= "
       "linear_max_iterations (30)"},
      {"negative lower limit", withKeys("  adaptive: true\n  lower_iterations: -1\n"), 15,
       "integrator.lower_iterations: expected an integer >= 0"},
      {"bounds in the wrong order",
       withKeys("  adaptive: true\n  min_step: 1e-3\n  max_step: 1e-4\n"), 16,
       "integrator.max_step: expected max_step >= min_step"},
      {"zero min step", withKeys("  adaptive: true\n  min_step: 0\n"), 15,
       "integrator.min_step: expected a positive number"},
      {"first step outside the bounds",
       withKeys("  adaptive: true\n  max_step: 1e-3\n  initial_step: 2e-3\n"), 16,
       "integrator.initial_step: expected min_step <= initial_step <= max_step"},
      {"unknown Jacobian", withKeys("  jacobian: numerical\n"), 14,
       "integrator.jacobian: expected one of: analytic, finite_difference; got 'numerical'"},
      {"coloring without finite differences", withKeys("  coloring: true\n"), 14,
       "integrator.coloring: applies only with jacobian: finite_difference"},
      {"coloring not a boolean", withKeys("  jacobian: finite_difference\n  coloring: 3\n"), 15,
       "integrator.coloring: expected true or false"},
      {"perturbation too large", withKeys("  jacobian: finite_difference\n  fd_epsilon: 0.1\n"),
       15, "integrator.fd_epsilon: expected a relative perturbation below 0.01"},
      {"negative position scale",
       withKeys("  jacobian: finite_difference\n  fd_position_scale: -1\n"), 15,
       "integrator.fd_position_scale: expected a positive number"},
      {"misspelt key", withKeys("  linear_solvr: gmres\n"), 14, "integrator.linear_solvr"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_be.yaml");
}

}  // namespace
}  // namespace tt
