// The law guccione and the model follower_pressure in a scene: the material's `guccione` map
// (C and bulk_modulus in the entry's stress_unit) reaches the law, the follower pressure's
// surface and pressure reach the model, and each malformed entry is one InputError naming the
// file, the line and the key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_util.h"
#include "tissue_trainer/core/material/guccione.h"
#include "tissue_trainer/core/model/follower_pressure.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

using testutil::replaced;
using testutil::writeScene;

// Line numbers below refer to this text.
const char* const kGuccioneScene = R"(name: guccione_patch
mesh: {generator: box, nodes: [3, 3, 3], size: [0.01, 0.01, 0.01], split: none}
fibres: {direction: [1, 1, 0]}
materials:
  - density: 1000
    stress_unit: kPa
    guccione: {C: 2, b_f: 8, b_t: 2, b_fs: 4, bulk_modulus: 100}
force_models:
  - {type: hyperelastic, law: guccione}
  - type: follower_pressure
    surface: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}
    stress_unit: kPa
    pressure: 0.004
integrator: {type: quasistatic}
boundary:
  fixed:
    - plane: {point: [0, 0, 0], normal: [1, 0, 0]}
)";

TEST(GuccioneScene, MaterialKeysReachTheLawAndPressureTheModel) {
  const Scene scene = loadScene(writeScene("guccione.yaml", kGuccioneScene));
  const System& s = scene.system;
  ASSERT_EQ(s.models.size(), 2u);
  // A homogeneous x = A X: the law's energy is V psi(A) at the scene's constants (in Pa).
  Eigen::Matrix3d A;
  A << 1.12, 0.04, -0.02, 0.03, 0.96, 0.05, -0.01, 0.02, 1.07;
  Eigen::VectorXd x(3 * s.mesh.numNodes());
  for (int n = 0; n < s.mesh.numNodes(); ++n) x.segment<3>(3 * n) = A * s.mesh.rest.col(n);
  const GuccioneConstants given{2000.0, 8.0, 2.0, 4.0, 1e5};
  const double psi = GuccioneLaw::energy(GuccioneLaw::parameters(given, s.mesh.hexFibreFrame[0]), A);
  EXPECT_NEAR(s.models[0]->energy(x), 1e-6 * psi, 1e-12 * 1e-6 * psi);
  // The bottom face: 2 x 2 quads, 8 triangles, 4 Pa.
  const auto* pressure = dynamic_cast<const FollowerPressureModel*>(s.models[1].get());
  ASSERT_NE(pressure, nullptr);
  EXPECT_EQ(pressure->faces().size(), 8u);
  EXPECT_DOUBLE_EQ(pressure->pressure(), 4.0);
}

TEST(GuccioneScene, EachMalformedEntryNamesFileLineAndKey) {
  const std::string scene = kGuccioneScene;
  const std::string map = "guccione: {C: 2, b_f: 8, b_t: 2, b_fs: 4, bulk_modulus: 100}";
  const std::vector<testutil::BadScene> cases = {
      {"no guccione map", replaced(scene, "    " + map + "\n", ""), 5,
       "materials[0]: missing guccione, which the guccione law reads"},
      {"no C", replaced(scene, map, "guccione: {b_f: 8, b_t: 2, b_fs: 4, bulk_modulus: 100}"), 7,
       "materials[0].guccione: missing C, which guccione reads"},
      {"no bulk modulus", replaced(scene, map, "guccione: {C: 2, b_f: 8, b_t: 2, b_fs: 4}"), 7,
       "materials[0].guccione: missing bulk_modulus"},
      {"negative C", replaced(scene, "C: 2", "C: -2"), 7,
       "materials[0].guccione.C: expected C > 0 (the stiffness C of C/2 (e^Q - 1)), got '-2'"},
      {"negative weight", replaced(scene, "b_t: 2", "b_t: -1"), 7,
       "materials[0].guccione.b_t: expected b_t >= 0"},
      {"zero bulk modulus", replaced(scene, "bulk_modulus: 100", "bulk_modulus: 0"), 7,
       "materials[0].guccione.bulk_modulus: expected bulk_modulus > 0"},
      {"a word for a number", replaced(scene, "b_fs: 4", "b_fs: four"), 7,
       "materials[0].guccione.b_fs: expected a finite number, got 'four'"},
      {"unknown key", replaced(scene, "b_fs: 4", "bfs: 4"), 7,
       "materials[0].guccione.bfs: unknown key 'bfs'"},
      {"no pressure", replaced(scene, "    pressure: 0.004\n", ""), 10,
       "force_models[1]: missing required key 'pressure'"},
      {"pressure not a number", replaced(scene, "pressure: 0.004", "pressure: high"), 13,
       "force_models[1].pressure: expected a finite number, got 'high'"},
      {"surface with no whole face", replaced(scene, "surface: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}",
                                              "surface: {nodes: [0, 1]}"),
       11, "force_models[1].surface: no boundary face of the mesh has all its nodes selected"},
      {"bad pressure curve",
       replaced(scene, "pressure: 0.004", "pressure: {type: piecewise_linear, times: [1, 0], values: [0, 1]}"),
       13, "force_models[1].pressure"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_guccione.yaml");
}

}  // namespace
}  // namespace tt
