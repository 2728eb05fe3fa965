// Malformed truncated_ellipsoid generators and ellipsoid fibres: each bad key is one InputError
// line naming the file, the line and the key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_util.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

using testutil::BadScene;
using testutil::replaced;
using testutil::writeScene;

// Line numbers refer to this text.
const char* const kBadVentricleScene = R"(mesh:
  generator: truncated_ellipsoid
  cells_transmural: 2
  cells_meridional: 8
  cells_circumferential: 16
  endocardium: [7, 17]
  epicardium: [10, 20]
  base_z: 5
  split: six
  length_unit: mm
fibres: {ellipsoid: {angles_deg: [60, -60]}}
materials: [{young_modulus: 3000, poisson_ratio: 0.3}]
force_models: [{type: hyperelastic, law: neo_hookean}]
integrator: {type: explicit_euler, time_step: 1.0e-5}
)";

std::string editedVentricle(const std::string& from, const std::string& to) {
  return replaced(kBadVentricleScene, from, to);
}

TEST(MalformedEllipsoid, GoodSceneLoads) {
  const Scene scene = loadScene(writeScene("good_ventricle.yaml", kBadVentricleScene));
  EXPECT_EQ(scene.system.numNodes(), 3 * (1 + 8 * 16));
}

TEST(MalformedEllipsoid, EachBadGeneratorKeyIsOneLineNamingIt) {
  const std::vector<BadScene> cases = {
      {"no cells through the wall", editedVentricle("cells_transmural: 2", "cells_transmural: 0"), 3,
       "mesh.cells_transmural: expected an integer >= 1, got"},
      {"one cell apex to base", editedVentricle("cells_meridional: 8", "cells_meridional: 1"), 4,
       "mesh.cells_meridional: expected an integer >= 2, got"},
      {"two cells around", editedVentricle("cells_circumferential: 16", "cells_circumferential: 2"), 5,
       "mesh.cells_circumferential: expected an integer >= 3, got"},
      {"fractional cells", editedVentricle("cells_circumferential: 16", "cells_circumferential: 7.5"), 5,
       "mesh.cells_circumferential: expected an integer, got"},
      {"one radius", editedVentricle("endocardium: [7, 17]", "endocardium: [7]"), 6,
       "mesh.endocardium: expected 2 radii [short, long]"},
      {"radii not a list", editedVentricle("endocardium: [7, 17]", "endocardium: 7"), 6,
       "mesh.endocardium: expected a list"},
      {"negative radius", editedVentricle("endocardium: [7, 17]", "endocardium: [-7, 17]"), 6,
       "mesh.endocardium[0]: expected a positive number"},
      {"radius not a number", editedVentricle("epicardium: [10, 20]", "epicardium: [10, wide]"), 7,
       "mesh.epicardium[1]: expected a finite number"},
      {"epicardium inside in r_s", editedVentricle("epicardium: [10, 20]", "epicardium: [6, 20]"), 7,
       "mesh.epicardium: expected epicardial radii larger than the endocardial ones: [6, 20] is "
       "not outside [7, 17]"},
      {"epicardium inside in r_l", editedVentricle("epicardium: [10, 20]", "epicardium: [10, 17]"), 7,
       "mesh.epicardium: expected epicardial radii larger"},
      {"endocardium outside the default epicardium",
       editedVentricle("  endocardium: [7, 17]\n  epicardium: [10, 20]\n", "  endocardium: [7, 25]\n"), 6,
       "mesh.endocardium: expected epicardial radii larger than the endocardial ones: [10, 20] "
       "is not outside [7, 25]"},
      {"cut above the endocardium", editedVentricle("base_z: 5", "base_z: 17"), 8,
       "mesh.base_z: expected 0 <= base_z < the endocardial long radius (17), got 17"},
      {"cut below the equator", editedVentricle("base_z: 5", "base_z: -1"), 8,
       "mesh.base_z: expected 0 <= base_z < the endocardial long radius (17), got -1"},
      {"cut not a number", editedVentricle("base_z: 5", "base_z: low"), 8,
       "mesh.base_z: expected a finite number"},
      {"default cut above a short endocardium",
       editedVentricle("  endocardium: [7, 17]\n  epicardium: [10, 20]\n  base_z: 5\n",
              "  endocardium: [7, 4]\n  epicardium: [10, 20]\n"),
       6, "mesh.endocardium: expected a long radius above the cut of the base (base_z 5), got 4"},
      {"five tets a cell", editedVentricle("split: six", "split: five_mirrored"), 9,
       "mesh.split: expected one of: none, six"},
      {"a box key", editedVentricle("split: six", "split: six\n  nodes: [3, 3, 3]"), 10,
       "mesh.nodes: unknown key 'nodes'"},
      {"unknown length unit", editedVentricle("length_unit: mm", "length_unit: inch"), 10,
       "mesh.length_unit: expected one of: m, cm, mm"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_ventricle.yaml");
}

TEST(MalformedEllipsoid, EachBadFibreKeyIsOneLineNamingIt) {
  const std::string fibres = "fibres: {ellipsoid: {angles_deg: [60, -60]}}";
  const std::vector<BadScene> cases = {
      {"one angle", editedVentricle(fibres, "fibres: {ellipsoid: {angles_deg: [60]}}"), 11,
       "fibres.ellipsoid.angles_deg: expected a list of 2 angles [at the endocardium, at the "
       "epicardium] in degrees"},
      {"angle not a number", editedVentricle(fibres, "fibres: {ellipsoid: {angles_deg: [60, steep]}}"), 11,
       "fibres.ellipsoid.angles_deg[1]: expected a finite number"},
      {"no angles", editedVentricle(fibres, "fibres: {ellipsoid: {}}"), 11,
       "fibres.ellipsoid: missing required key 'angles_deg'"},
      {"not a map", editedVentricle(fibres, "fibres: {ellipsoid: [60, -60]}"), 11,
       "fibres.ellipsoid: expected a map"},
      {"unknown key", editedVentricle(fibres, "fibres: {ellipsoid: {angles_deg: [60, -60], normal: [0, 0, 1]}}"), 11,
       "fibres.ellipsoid.normal: unknown key 'normal'"},
      {"two forms", editedVentricle(fibres, "fibres: {direction: [1, 0, 0], ellipsoid: {angles_deg: [60, -60]}}"), 11,
       "fibres.ellipsoid: expected one form of fibres"},
      {"in a material", editedVentricle("poisson_ratio: 0.3}", "poisson_ratio: 0.3, fibres: {ellipsoid: {angles_deg: [1, 2, 3]}}}"), 12,
       "materials[0].fibres.ellipsoid.angles_deg: expected a list of 2 angles"},
      {"on a box", editedVentricle("  generator: truncated_ellipsoid\n  cells_transmural: 2\n  cells_meridional: 8\n"
                          "  cells_circumferential: 16\n  endocardium: [7, 17]\n  epicardium: [10, 20]\n"
                          "  base_z: 5\n  split: six\n",
                          "  generator: box\n  nodes: [3, 3, 3]\n  size: [10, 10, 10]\n"),
       6, "fibres.ellipsoid: expected a mesh of generator truncated_ellipsoid"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_ventricle_fibres.yaml");
}

}  // namespace
}  // namespace tt
