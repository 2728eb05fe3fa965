// Malformed targets files of a landmark fit: one error line naming the file and the line.
#include <gtest/gtest.h>

#include "../scene/scene_test_util.h"
#include "tissue_trainer/core/fit/landmark_fit.h"

namespace tt {
namespace {

TEST(MalformedLandmarks, EachBadLineGivesOneErrorLineWithFileAndLine) {
  const Scene scene = loadScene(testutil::writeScene("landmark_block.yaml", R"(name: block
mesh: {generator: box, nodes: [2, 2, 2], size: [1, 1, 1]}
materials: [{young_modulus: 1, poisson_ratio: 0.3}]
force_models: [{type: hyperelastic, law: neo_hookean}]
integrator: {type: quasistatic}
)"));
  const Mesh& mesh = scene.system.mesh;
  const std::string good = "# targets\n\nnode 0 0 0 0\ntet 0 0.25 0.25 0.25 0.25 1 2 3  # c\n";
  const std::vector<testutil::BadScene> cases = {
      {"too few numbers", good + "node 1 0 0\n", 5, "expects 4 numbers"},
      {"too many numbers", good + "tet 0 0.25 0.25 0.25 0.25 1 2 3 4\n", 5, "expects 8 numbers"},
      {"unknown kind", good + "vertex 1 0 0 0\n", 5, "expected 'N x y z' (node index and target)"},
      {"five numbers", good + "1 0 0 0 0\n", 5, "or 'T b0 b1 b2 b3 x y z'"},
      {"numeric node out of range", good + "8 0 0 0\n", 5, "node index 8 out of range"},
      {"numeric tet weights", good + "0 0.5 0.5 0.5 0 0 0 0\n", 5, "sum to 1"},
      {"node out of range", good + "node 8 0 0 0\n", 5, "node index 8 out of range"},
      {"negative node", good + "node -1 0 0 0\n", 5, "out of range"},
      {"fractional node", good + "node 1.5 0 0 0\n", 5, "out of range"},
      {"tet out of range", "tet " + std::to_string(mesh.numTets()) + " 1 0 0 0 0 0 0\n", 1,
       "tet index"},
      {"weights not summing to 1", good + "tet 0 0.3 0.3 0.3 0.3 0 0 0\n", 5, "sum to 1"},
      {"negative weight", good + "tet 0 1.5 -0.5 0 0 0 0 0\n", 5, "must not be negative"},
      {"not a number", good + "node 1 0 zero 0\n", 5, "expected a finite number, got 'zero'"},
      {"infinite coordinate", good + "node 1 0 inf 0\n", 5, "finite number"},
      {"no landmarks", "# nothing\n\n", 0, "no landmarks"},
  };
  testutil::expectEachFileFailsClearly(cases, "targets.txt", [&](const std::string& path) {
    readLandmarks(path, mesh);
  });
}

TEST(MalformedLandmarks, AGoodFileReadsNodeAndTetLandmarks) {
  const Scene scene = loadScene(testutil::writeScene("landmark_block2.yaml", R"(name: block
mesh: {generator: box, nodes: [2, 2, 2], size: [1, 1, 1]}
materials: [{young_modulus: 1, poisson_ratio: 0.3}]
force_models: [{type: hyperelastic, law: neo_hookean}]
integrator: {type: quasistatic}
)"));
  const std::string path = testutil::writeScene(
      "targets_good.txt",
      "# targets\n\nnode 3 0.5 0 -1\n  tet 1 0.1 0.2 0.3 0.4 1 2 3  # c\n"
      "3 0.5 0 -1\n1 0.1 0.2 0.3 0.4 1 2 3\n");  // the same without the words
  const std::vector<Landmark> l = readLandmarks(path, scene.system.mesh);
  ASSERT_EQ(l.size(), 4u);
  for (int k : {0, 1}) {
    EXPECT_EQ(l[k + 2].nodes, l[k].nodes);
    EXPECT_EQ(l[k + 2].weights, l[k].weights);
    EXPECT_EQ(l[k + 2].target, l[k].target);
  }
  EXPECT_EQ(l[0].nodes[0], 3);
  EXPECT_EQ(l[0].weights, Eigen::Vector4d(1, 0, 0, 0));
  EXPECT_EQ(l[0].target, Eigen::Vector3d(0.5, 0, -1));
  EXPECT_EQ(l[1].nodes, scene.system.mesh.tets[1]);
  EXPECT_EQ(l[1].weights, Eigen::Vector4d(0.1, 0.2, 0.3, 0.4));
  EXPECT_EQ(l[1].target, Eigen::Vector3d(1, 2, 3));
}

}  // namespace
}  // namespace tt
