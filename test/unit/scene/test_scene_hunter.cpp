// The Hunter laws in a scene: a material's `hunter` map (k in the entry's stress_unit, Table
// 2.1 where left out) and `hunter_polynomial` map reach the laws, and each malformed entry is
// one InputError naming the file, the line and the key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scene_test_util.h"
#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/hunter_polynomial.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

// Line numbers below refer to this text.
const char* const kHunterScene = R"(name: myocardium_patch
mesh: {generator: box, nodes: [3, 3, 3], size: [0.01, 0.01, 0.01]}
fibres: {direction: [1, 1, 0]}
materials:
  - young_modulus: 3
    poisson_ratio: 0.4
    stress_unit: kPa
    hunter:
      k: [3.0, 0.1, 0.5, 1.5, 1.2, 0.9]
      a: [0.35, 0.45, 1.1, 0.8, 0.75, 0.9]
      b: [0.7, 2.0, 0.4, 2.1, 1.9, 2.2]
force_models:
  - type: hyperelastic
    law: LAW
integrator: {type: backward_euler}
)";

using testutil::writeScene;

using testutil::replaced;

std::string withLaw(const std::string& law) { return replaced(kHunterScene, "LAW", law); }

// The model's energy under a homogeneous deformation x = A X is V psi(A), psi the law's at
// the constants the scene should have given it (the elements share one fibre frame).
template <class Law>
void expectLawConstants(const Scene& scene, const typename Law::Constants& expected) {
  const System& s = scene.system;
  ASSERT_EQ(s.models.size(), 1u);
  Eigen::Matrix3d A;
  A << 1.12, 0.04, -0.02, 0.03, 0.96, 0.05, -0.01, 0.02, 1.07;
  Eigen::VectorXd x(3 * s.mesh.numNodes());
  for (int n = 0; n < s.mesh.numNodes(); ++n) x.segment<3>(3 * n) = A * s.mesh.rest.col(n);
  const double psi = Law::energy(Law::parameters(expected, s.mesh.fibreFrame[0]), A);
  EXPECT_NEAR(s.models[0]->energy(x), 1e-6 * psi, 1e-12 * 1e-6 * psi);
}

TEST(HunterScene, MaterialKeysReachTheLaws) {
  HunterConstants given;
  given.k = {3000.0, 100.0, 500.0, 1500.0, 1200.0, 900.0};  // kPa in the scene
  given.a = {0.35, 0.45, 1.1, 0.8, 0.75, 0.9};
  given.b = {0.7, 2.0, 0.4, 2.1, 1.9, 2.2};
  {
    const Scene scene = loadScene(writeScene("hunter.yaml", withLaw("hunter")));
    expectLawConstants<HunterLaw>(scene, given);
    // The frame is the scene's: fibre along (1, 1, 0).
    EXPECT_NEAR(scene.system.mesh.fibreFrame[0].col(0).dot(Eigen::Vector3d(1, 1, 0).normalized()),
                1.0, 1e-15);
  }
  {
    // Without the map, and with only some lists: Table 2.1 (k in kPa) for what is left out.
    const std::string map = "    hunter:\n      k: [3.0, 0.1, 0.5, 1.5, 1.2, 0.9]\n"
                            "      a: [0.35, 0.45, 1.1, 0.8, 0.75, 0.9]\n"
                            "      b: [0.7, 2.0, 0.4, 2.1, 1.9, 2.2]\n";
    const Scene none = loadScene(writeScene("hunter_default.yaml",
                                            replaced(withLaw("hunter"), map, "")));
    expectLawConstants<HunterLaw>(none, HunterConstants::table21());
    const Scene empty = loadScene(writeScene("hunter_empty.yaml",
                                             replaced(withLaw("hunter"), map, "    hunter: {}\n")));
    expectLawConstants<HunterLaw>(empty, HunterConstants::table21());
    HunterConstants onlyA = HunterConstants::table21();
    onlyA.a = given.a;
    const Scene partial = loadScene(writeScene(
        "hunter_partial.yaml",
        replaced(withLaw("hunter"), map, "    hunter:\n      a: [0.35, 0.45, 1.1, 0.8, 0.75, 0.9]\n")));
    expectLawConstants<HunterLaw>(partial, onlyA);
  }
  {
    HunterPolynomialLaw::Constants c;
    c.hunter = given;
    const Scene defaults = loadScene(writeScene("hunter_poly.yaml", withLaw("hunter_polynomial")));
    expectLawConstants<HunterPolynomialLaw>(defaults, c);
    c.switchFraction = 0.5;  // the deformation above passes this switch on the fibre term
    c.degree = 5;
    const Scene options = loadScene(writeScene(
        "hunter_poly_options.yaml",
        replaced(withLaw("hunter_polynomial"), "force_models:",
                 "    hunter_polynomial: {switch_fraction: 0.5, degree: 5}\nforce_models:")));
    expectLawConstants<HunterPolynomialLaw>(options, c);
  }
}

using testutil::BadScene;

TEST(HunterScene, EachMalformedEntryNamesFileLineAndKey) {
  const std::string hunter = withLaw("hunter"), poly = withLaw("hunter_polynomial");
  const std::string k = "k: [3.0, 0.1, 0.5, 1.5, 1.2, 0.9]";
  const std::string a = "a: [0.35, 0.45, 1.1, 0.8, 0.75, 0.9]";
  const std::string b = "b: [0.7, 2.0, 0.4, 2.1, 1.9, 2.2]";
  const auto polyWith = [&](const std::string& map) {
    return replaced(poly, "force_models:", "    hunter_polynomial: " + map + "\nforce_models:");
  };
  const std::vector<BadScene> cases = {
      {"five stiffnesses", replaced(hunter, k, "k: [3.0, 0.1, 0.5, 1.5, 1.2]"), 9,
       "materials[0].hunter.k: expected a list of 6 numbers k11, k22, k33, k12, k13, k23, got 5"},
      {"seven poles", replaced(hunter, a, "a: [0.35, 0.45, 1.1, 0.8, 0.75, 0.9, 1]"), 10,
       "materials[0].hunter.a: expected a list of 6 numbers a11, a22, a33, a12, a13, a23, got 7"},
      {"exponents not a list", replaced(hunter, b, "b: 2"), 11,
       "materials[0].hunter.b: expected a list, got '2'"},
      {"negative stiffness", replaced(hunter, k, "k: [3.0, 0.1, 0.5, -1.5, 1.2, 0.9]"), 9,
       "materials[0].hunter.k[3]: expected k12 >= 0, got '-1.5'"},
      {"pole at zero", replaced(hunter, a, "a: [0, 0.45, 1.1, 0.8, 0.75, 0.9]"), 10,
       "materials[0].hunter.a[0]: expected a11 > 0 (the pole"},
      {"negative pole", replaced(hunter, a, "a: [0.35, 0.45, 1.1, 0.8, 0.75, -0.9]"), 10,
       "materials[0].hunter.a[5]: expected a23 > 0 (the pole"},
      {"negative exponent", replaced(hunter, b, "b: [0.7, 2.0, -0.4, 2.1, 1.9, 2.2]"), 11,
       "materials[0].hunter.b[2]: expected b33 >= 0 (an exponent), got '-0.4'"},
      {"a word for a number", replaced(hunter, k, "k: [3.0, 0.1, soft, 1.5, 1.2, 0.9]"), 9,
       "materials[0].hunter.k[2]: expected a finite number, got 'soft'"},
      {"unknown key in the map", replaced(hunter, b, "beta: [0.7, 2.0, 0.4, 2.1, 1.9, 2.2]"), 11,
       "materials[0].hunter.beta: unknown key 'beta' (expected one of: k, a, b)"},
      {"map given as a list",
       replaced(hunter, "    hunter:\n      " + k + "\n      " + a + "\n      " + b, "    hunter: [1, 2]"),
       8, "materials[0].hunter: expected a map, got a list"},
      // (the line of the map's first key: a block map starts there)
      {"hunter map with no model reading it", replaced(hunter, "law: hunter", "law: stvk"), 9,
       "materials[0].hunter: read by the law 'hunter', which no force model of this scene uses"},
      {"polynomial map with the pole-zero law",
       replaced(hunter, "force_models:", "    hunter_polynomial: {degree: 4}\nforce_models:"), 12,
       "materials[0].hunter_polynomial: read by the law 'hunter_polynomial', which no force model"},
      {"switch at the pole", polyWith("{switch_fraction: 1}"), 12,
       "materials[0].hunter_polynomial.switch_fraction: expected a fraction of the pole in (0, 1), got '1'"},
      {"switch at zero", polyWith("{switch_fraction: 0}"), 12, "in (0, 1), got '0'"},
      {"degree 1", polyWith("{degree: 1}"), 12,
       "materials[0].hunter_polynomial.degree: expected an integer >= 2, got '1'"},
      {"degree 7", polyWith("{degree: 7}"), 12,
       "materials[0].hunter_polynomial.degree: expected a degree in [2, 6], got '7'"},
      {"fractional degree", polyWith("{degree: 2.5}"), 12, "expected an integer, got '2.5'"},
      {"unknown polynomial key", polyWith("{order: 3}"), 12,
       "materials[0].hunter_polynomial.order: unknown key 'order' (expected one of: switch_fraction, degree)"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_hunter.yaml");
}

// The virtual hexahedron reads the same law and material keys; on this tet mesh it is the
// hyperelastic model's element exactly.
TEST(HunterScene, VirtualHexahedronReadsTheLawOfItsEntry) {
  const std::string vh = replaced(withLaw("hunter"), "type: hyperelastic", "type: virtual_hexahedron");
  const Scene a = loadScene(writeScene("vh.yaml", vh));
  const Scene b = loadScene(writeScene("fem.yaml", withLaw("hunter")));
  EXPECT_STREQ(a.system.models[0]->name(), "virtual_hexahedron");
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(b.system.mesh.rest.data(),
                                                         3 * b.system.mesh.numNodes());
  for (int i = 0; i < x.size(); i += 3) x[i] *= 1.1;
  EXPECT_NEAR(a.system.models[0]->energy(x), b.system.models[0]->energy(x),
              1e-12 * b.system.models[0]->energy(x));
  const Scene approx = loadScene(writeScene(
      "vh_approx.yaml",
      replaced(replaced(vh, "law: hunter", "law: hunter\n    deformation_gradient: axis_approximation"),
               "backward_euler", "symplectic_euler")));
  EXPECT_FALSE(approx.system.models[0]->hasStiffness());
}

TEST(HunterScene, MalformedVirtualHexahedronEntriesNameFileLineAndKey) {
  const std::string vh = replaced(withLaw("hunter"), "type: hyperelastic", "type: virtual_hexahedron");
  const auto with = [&](const std::string& line) {
    return replaced(vh, "law: hunter", "law: hunter\n    " + line);
  };
  const std::vector<BadScene> cases = {
      {"unknown source", with("deformation_gradient: axes"), 15,
       "force_models[0].deformation_gradient: expected one of: shape_functions, axis_approximation"},
      {"unknown law", replaced(vh, "law: hunter", "law: huntr"), 14,
       "force_models[0].law: unknown law 'huntr'"},
      {"approximation has no stiffness for an implicit integrator",
       with("deformation_gradient: axis_approximation"), 16,
       "integrator.type: backward_euler needs the stiffness of every force model; "
       "virtual_hexahedron provides none"},
      {"bad threshold", with("inversion_threshold: 1.5"), 15,
       "force_models[0].inversion_threshold: expected a threshold in [0, 1)"},
      {"diagonal-blocks projection of a law without one",
       with("psd_projection: true\n    psd_method: diagonal_blocks"), 13,
       "force_models[0]: psd_method: diagonal_blocks needs law teran_muscle or an isotropic "
       "law, not hunter (use psd_method: eigen)"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_vh.yaml");
}

// The fibre frame from a direction and a sheet, or from spherical angles.
TEST(HunterScene, FibreFrameFromSheetOrAngles) {
  const std::string base = withLaw("hunter");
  const Scene sheet = loadScene(writeScene(
      "sheet.yaml", replaced(base, "fibres: {direction: [1, 1, 0]}",
                             "fibres: {direction: [1, 1, 0], sheet: [0, 0, 3]}")));
  Eigen::Matrix3d expected;
  expected.col(0) = Eigen::Vector3d(1, 1, 0).normalized();
  expected.col(1) = Eigen::Vector3d::UnitZ();
  expected.col(2) = expected.col(0).cross(expected.col(1));
  EXPECT_LT((sheet.system.mesh.fibreFrame[3] - expected).norm(), 1e-15);
  // phi 90, theta 90: fibre +y, sheet -z (d fibre / d theta), normal y x -z = -x.
  const Scene angles = loadScene(writeScene(
      "angles.yaml", replaced(base, "fibres: {direction: [1, 1, 0]}", "fibres: {angles_deg: [90, 90]}")));
  expected << 0, 0, -1, 1, 0, 0, 0, -1, 0;
  EXPECT_LT((angles.system.mesh.fibreFrame[0] - expected).norm(), 1e-15);
  const Scene tilted = loadScene(writeScene(
      "tilted.yaml", replaced(base, "fibres: {direction: [1, 1, 0]}", "fibres: {angles_deg: [21.25, 49.6]}")));
  const Eigen::Matrix3d B = tilted.system.mesh.fibreFrame[0];
  EXPECT_TRUE((B.transpose() * B).isIdentity(1e-15));
  EXPECT_NEAR(B.determinant(), 1.0, 1e-15);
  EXPECT_NEAR(B(2, 0), std::cos(49.6 * M_PI / 180), 1e-15);
}

TEST(HunterScene, MalformedFibreEntriesNameFileLineAndKey) {
  const std::string base = withLaw("hunter");
  const auto with = [&](const std::string& fibres) {
    return replaced(base, "fibres: {direction: [1, 1, 0]}", "fibres: " + fibres);
  };
  const std::vector<BadScene> cases = {
      {"sheet along the fibre", with("{direction: [1, 1, 0], sheet: [1, 0, 0]}"), 3,
       "fibres.sheet: expected a sheet direction orthogonal to the fibre direction, got cosine 0.7071"},
      {"zero sheet", with("{direction: [1, 1, 0], sheet: [0, 0, 0]}"), 3,
       "fibres.sheet: expected a non-zero sheet direction"},
      {"angles and direction", with("{direction: [1, 1, 0], angles_deg: [10, 20]}"), 3,
       "fibres.angles_deg: expected either angles_deg or direction (and sheet), not both"},
      {"three angles", with("{angles_deg: [10, 20, 30]}"), 3,
       "fibres.angles_deg: expected a list of 2 angles [phi, theta] in degrees"},
      {"sheet alone", with("{sheet: [0, 0, 1]}"), 3, "fibres: missing required key 'direction'"},
      {"unknown key", with("{direction: [1, 1, 0], normal: [0, 0, 1]}"), 3,
       "fibres.normal: unknown key 'normal' (expected one of: direction, sheet, angles_deg, file, transmural, ellipsoid)"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_fibres.yaml");
}

}  // namespace
}  // namespace tt
