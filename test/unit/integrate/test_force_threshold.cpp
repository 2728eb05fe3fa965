// The Newtonian integrator's force threshold (Jeffrey, "A non-linear anisotropic Finite
// Element Method for surgical simulation", Sec. 3): off by default; when on, exactly the free
// nodes whose net force m a = F - gamma v is below the threshold at the start of a step keep
// their position (and get zero velocity); the others are propagated.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/integrate/newtonian.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

// A 3 x 3 x 3-node block, bottom fixed, the top corner dragged sideways.
System draggedBlock() {
  Mesh mesh = boxGrid(3, 3, 3, Eigen::Vector3d::Constant(0.02), TetSplit::kFiveMirrored);
  int corner = -1;
  for (int a = 0; a < mesh.numNodes(); ++a) {
    if (mesh.rest(2, a) < 1e-9) mesh.nodeTags[a] = kFixedAll;
    if ((mesh.rest.col(a) - Eigen::Vector3d(0, 0, 0.02)).norm() < 1e-9) corner = a;
  }
  const std::vector<Material> materials = {Material::isotropic(2e4, 0.4, 1000.0)};
  System s(mesh, materials);
  s.damping = 20.0 * s.mass;
  s.models.push_back(std::make_unique<EdgeLengthModel>(s.mesh, materials));
  s.controlled.push_back(
      {{corner}, {{0.0, 0.05}, {Eigen::Vector3d::Zero(), Eigen::Vector3d(0.005, 0, 0)}}});
  s.updateConstraints();
  return s;
}

TEST(ForceThreshold, OffByDefault) {
  EXPECT_EQ(NewtonianParams{}.forceThreshold, 0.0);
  // A lone free node under a tiny force still moves, by 1/2 a t^2.
  Mesh mesh = boxGrid(2, 2, 2, Eigen::Vector3d::Constant(0.01), TetSplit::kFive);
  System s(mesh, {Material::isotropic(1e3, 0.3, 1000.0)});
  s.externalForce[0] = 1e-12;  // N, on node 0 only; no models, no damping
  NewtonianIntegrator newtonian(NewtonianParams{1e-3});
  ASSERT_TRUE(newtonian.advance(s, 0.01).ok);
  const double expected = 0.5 * 1e-12 / s.mass[0] * 0.01 * 0.01;
  EXPECT_NEAR(s.state.x[0] - mesh.rest(0, 0), expected, 1e-6 * expected);
  EXPECT_EQ(newtonian.frozenNodeSteps(), 0);

  NewtonianIntegrator thresholded(NewtonianParams{1e-3, false, 1e-9});
  System t(mesh, {Material::isotropic(1e3, 0.3, 1000.0)});
  t.externalForce[0] = 1e-12;
  ASSERT_TRUE(thresholded.advance(t, 0.01).ok);
  EXPECT_EQ(t.state.x[0], mesh.rest(0, 0));
  EXPECT_EQ(thresholded.frozenNodeSteps(), 10L * 8);  // 10 steps, 8 free nodes
}

// Step by step: a node is frozen exactly when its net force at the step start is below the
// threshold; frozen nodes keep x and get v = 0, the others move.
TEST(ForceThreshold, FreezesExactlyTheLowForceNodes) {
  System s = draggedBlock();
  const double h = 1e-4;
  const double threshold = 2e-4;  // N; the dragged block's nodal forces span this value
  NewtonianIntegrator newtonian(NewtonianParams{h, false, threshold});
  Eigen::VectorXd f;
  int frozenSeen = 0, movedSeen = 0;
  for (int step = 0; step < 600; ++step) {
    const State before = s.state;
    s.computeForce(before.x, before.v, f);  // includes -gamma v: Eq 10's right-hand side
    const long countBefore = newtonian.frozenNodeSteps();
    ASSERT_TRUE(newtonian.advance(s, h).ok);
    long frozenNow = 0;
    for (int a = 0; a < s.numNodes(); ++a) {
      if (s.mesh.nodeTags[a] != 0) continue;  // fixed bottom and the dragged corner
      const bool low = f.segment<3>(3 * a).norm() < threshold;
      const bool kept = s.state.x.segment<3>(3 * a) == before.x.segment<3>(3 * a);
      EXPECT_EQ(low, kept) << "node " << a << " step " << step;
      if (low) {
        EXPECT_TRUE(s.state.v.segment<3>(3 * a).isZero());
        ++frozenSeen;
        ++frozenNow;
      } else {
        ++movedSeen;
      }
    }
    EXPECT_EQ(newtonian.frozenNodeSteps() - countBefore, frozenNow);
  }
  EXPECT_GT(frozenSeen, 100);  // both kinds occur, so the test can fail either way
  EXPECT_GT(movedSeen, 100);
}

std::string writeScene(const std::string& integrator) {
  const auto dir = std::filesystem::temp_directory_path() / "tt_force_threshold_tests";
  std::filesystem::create_directories(dir);
  const auto path = dir / "scene.yaml";
  std::ofstream(path) << "name: block\n"
                         "mesh: {generator: box, nodes: [3, 3, 3], size: [0.02, 0.02, 0.02]}\n"
                         "materials:\n"
                         "  - {young_modulus: 3000, poisson_ratio: 0.4, density: 1000}\n"
                         "force_models:\n"
                         "  - type: edge_length\n"
                         "integrator:\n" << integrator <<
                         "run: {frame_time: 0.01, duration: 0.05}\n";
  return path.string();
}

TEST(ForceThreshold, SceneKey) {
  Scene plain = loadScene(writeScene("  type: newtonian\n  time_step: 0.0001\n"));
  auto* a = dynamic_cast<NewtonianIntegrator*>(&unguarded(*plain.integrator));
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a->params().forceThreshold, 0.0);

  Scene on = loadScene(writeScene("  type: newtonian\n  force_threshold: 0.002\n"));
  auto* b = dynamic_cast<NewtonianIntegrator*>(&unguarded(*on.integrator));
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(b->params().forceThreshold, 0.002);

  try {
    loadScene(writeScene("  type: newtonian\n  force_threshold: -1\n"));
    ADD_FAILURE() << "a negative threshold was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("force_threshold"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tt
