// The muscle law in a scene: a material's `teran_muscle` map (stresses in the entry's
// stress_unit, PhysBAM's defaults where left out) reaches the law, and each malformed entry
// is one InputError naming the file, the line and the key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_util.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

// Line numbers below refer to this text.
const char* const kMuscleScene = R"(name: muscle_patch
mesh: {generator: box, nodes: [3, 3, 3], size: [0.01, 0.01, 0.01]}
fibres: {direction: [1, 1, 0]}
materials:
  - young_modulus: 60
    poisson_ratio: 0.45
    stress_unit: kPa
    teran_muscle:
      mooney_rivlin: [50, 10]
      bulk: 400
      peak_stress: 200
      activation: 0.4
      fiber_stretch: nondeviatoric
force_models:
  - type: hyperelastic
    law: teran_muscle
integrator: {type: backward_euler}
)";

using testutil::writeScene;

using testutil::replaced;

// The model's energy under x = A X is V psi(A) with the constants the scene should give.
void expectConstants(const Scene& scene, const TeranMuscleLaw::Constants& k) {
  const System& s = scene.system;
  ASSERT_EQ(s.models.size(), 1u);
  Eigen::Matrix3d A;
  A << 1.12, 0.04, -0.02, 0.03, 0.96, 0.05, -0.01, 0.02, 1.07;
  Eigen::VectorXd x(3 * s.mesh.numNodes());
  for (int n = 0; n < s.mesh.numNodes(); ++n) x.segment<3>(3 * n) = A * s.mesh.rest.col(n);
  const double psi =
      TeranMuscleLaw::energy(TeranMuscleLaw::parameters(k, s.mesh.fibreFrame[0]), A);
  EXPECT_NEAR(s.models[0]->energy(x), 1e-6 * psi, 1e-12 * 1e-6 * psi);
}

TEST(TeranMuscleScene, MaterialKeysReachTheLaw) {
  TeranMuscleLaw::Constants given;
  given.A = 5e4, given.B = 1e4, given.K = 4e5, given.sigmaMax = 2e5, given.activation = 0.4;
  given.deviatoricStretch = false;
  expectConstants(loadScene(writeScene("muscle.yaml", kMuscleScene)), given);
  // Without the map: PhysBAM's defaults.
  const std::string bare = replaced(
      kMuscleScene,
      "    teran_muscle:\n      mooney_rivlin: [50, 10]\n      bulk: 400\n      peak_stress: 200\n"
      "      activation: 0.4\n      fiber_stretch: nondeviatoric\n",
      "");
  expectConstants(loadScene(writeScene("muscle_defaults.yaml", bare)), TeranMuscleLaw::Constants{});
}

TEST(TeranMuscleScene, EachMalformedEntryNamesFileLineAndKey) {
  const std::string s = kMuscleScene;
  const std::vector<testutil::BadScene> cases = {
      {"three Mooney-Rivlin constants", replaced(s, "[50, 10]", "[50, 10, 3]"), 9,
       "materials[0].teran_muscle.mooney_rivlin: expected a list of 2 numbers A, B, got 3"},
      {"negative bulk", replaced(s, "bulk: 400", "bulk: -4"), 10,
       "materials[0].teran_muscle.bulk: expected a stress >= 0, got '-4'"},
      {"activation above 1", replaced(s, "activation: 0.4", "activation: 1.5"), 12,
       "materials[0].teran_muscle.activation: expected an activation in [0, 1], got '1.5'"},
      {"unknown stretch", replaced(s, "fiber_stretch: nondeviatoric", "fiber_stretch: isochoric"),
       13, "materials[0].teran_muscle.fiber_stretch"},
      {"unknown key", replaced(s, "bulk: 400", "kappa: 400"), 10,
       "materials[0].teran_muscle.kappa: unknown key 'kappa'"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_muscle.yaml");
}

// psd_method picks the projection of the entry's model: the default is eigen; diagonal_blocks
// gives the products of a model built with PsdMethod::kDiagonalBlocks, which differ from the
// eigenvalue clamp's where the tangent is indefinite.
TEST(TeranMuscleScene, PsdMethodReachesTheModel) {
  const auto withKeys = [](const std::string& keys) {
    return replaced(kMuscleScene, "    law: teran_muscle\n", "    law: teran_muscle\n" + keys);
  };
  const Scene byDefault = loadScene(writeScene("psd_default.yaml", withKeys("    psd_projection: true\n")));
  const Scene eigen = loadScene(writeScene(
      "psd_eigen.yaml", withKeys("    psd_projection: true\n    psd_method: eigen\n")));
  const Scene blocks = loadScene(writeScene(
      "psd_blocks.yaml", withKeys("    psd_projection: true\n    psd_method: diagonal_blocks\n")));
  const Mesh& mesh = blocks.system.mesh;
  TeranMuscleLaw::Constants k;
  k.A = 5e4, k.B = 1e4, k.K = 4e5, k.sigmaMax = 2e5, k.activation = 0.4;
  k.deviatoricStretch = false;
  LawOptions options;
  options.psdProjection = true;
  options.psdMethod = PsdMethod::kDiagonalBlocks;
  const HyperelasticModel<TeranMuscleLaw> direct(mesh, {k}, options);
  // Compressed across the fibre, stretched along it (lam > 1: tau' < 0 for the active curve).
  Eigen::Matrix3d A;
  A << 1.25, 0.1, 0.0, 0.05, 0.55, 0.02, 0.0, 0.03, 0.7;
  Eigen::VectorXd x(3 * mesh.numNodes()), d(3 * mesh.numNodes());
  for (int n = 0; n < mesh.numNodes(); ++n) {
    x.segment<3>(3 * n) = A * mesh.rest.col(n);
    d.segment<3>(3 * n) = Eigen::Vector3d(std::sin(n), std::cos(3.0 * n), std::sin(7.0 * n));
  }
  const auto product = [&](const ForceModel& m) {
    Eigen::VectorXd out = Eigen::VectorXd::Zero(x.size());
    m.addStiffnessTimes(x, d, 1.0, out);
    return out;
  };
  const Eigen::VectorXd pd = product(*byDefault.system.models[0]);
  const Eigen::VectorXd pe = product(*eigen.system.models[0]);
  const Eigen::VectorXd pb = product(*blocks.system.models[0]);
  EXPECT_EQ(pd, pe);
  const auto relative = [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return (a - b).lpNorm<Eigen::Infinity>() / b.lpNorm<Eigen::Infinity>();
  };
  EXPECT_LT(relative(pb, product(direct)), 1e-12);
  EXPECT_GT(relative(pb, pe), 1e-6);
}

TEST(TeranMuscleScene, MalformedPsdMethodNamesFileLineAndKey) {
  const auto withKeys = [](const std::string& keys) {
    return replaced(kMuscleScene, "    law: teran_muscle\n", "    law: teran_muscle\n" + keys);
  };
  const std::vector<testutil::BadScene> cases = {
      {"unknown method", withKeys("    psd_projection: true\n    psd_method: newton\n"), 18,
       "force_models[0].psd_method: expected one of: eigen, diagonal_blocks; got 'newton'"},
      {"method without projection", withKeys("    psd_method: diagonal_blocks\n"), 17,
       "force_models[0].psd_method: applies with psd_projection: true only"},
      {"method with projection off",
       withKeys("    psd_projection: false\n    psd_method: eigen\n"), 18,
       "force_models[0].psd_method: applies with psd_projection: true only"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_psd_method.yaml");
}

}  // namespace
}  // namespace tt
