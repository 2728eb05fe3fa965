// Boundary conditions per axis ("Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.6):
// fixation and control tags per axis from the scene or from an index file of "node tags"
// lines, controlled axes following a path, a velocity or a step per frame.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "scene_test_util.h"
#include "tissue_trainer/core/mesh/node_tags.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

using testutil::replaced;
using testutil::writeScene;

// 3 x 3 x 3 nodes, 2 cm: node i + 3 j + 9 k at (i, j, k) cm.
const char* const kScene = R"(mesh: {generator: box, nodes: [3, 3, 3], size: [0.02, 0.02, 0.02]}
materials: [{young_modulus: 3000, poisson_ratio: 0.3}]
force_models: [{type: edge_length}]
integrator: {type: backward_euler}
run: {frame_time: 0.02}
boundary: BOUNDARY
)";

std::set<int> constrained(const System& s) {
  return std::set<int>(s.constrainedDofs.begin(), s.constrainedDofs.end());
}

TEST(BoundaryTags, SceneFixesAndControlsSingleAxes) {
  const std::string boundary = R"(
  fixed: [{plane: {point: [0, 0, 0], normal: [0, 0, 1]}, axes: z}]
  controlled:
    - plane: {point: [0, 0, 0.02], normal: [0, 0, 1]}
      axes: z
      step: [0, 0, 0.0001]
)";
  Scene scene = loadScene(writeScene("axis_tags.yaml", replaced(kScene, "BOUNDARY", boundary)));
  System& s = scene.system;
  ASSERT_EQ(s.numNodes(), 27);
  std::set<int> expected;
  for (int n = 0; n < 9; ++n) expected.insert(3 * n + 2);        // bottom: z
  for (int n = 18; n < 27; ++n) expected.insert(3 * n + 2);      // top: z
  EXPECT_EQ(constrained(s), expected);
  // 0.1 mm per frame of 0.02 s: 5 mm/s along z; x and y are left as they are.
  Eigen::VectorXd x = Eigen::VectorXd::Constant(81, 7.0), v = Eigen::VectorXd::Constant(81, 7.0);
  s.prescribe(0.5, x, v);
  for (int n = 0; n < 27; ++n) {
    EXPECT_EQ(x[3 * n], 7.0);
    EXPECT_EQ(x[3 * n + 1], 7.0);
    if (n < 9) {
      EXPECT_EQ(x[3 * n + 2], 0.0);
      EXPECT_EQ(v[3 * n + 2], 0.0);
    } else if (n >= 18) {
      EXPECT_NEAR(x[3 * n + 2], 0.02 + 0.0025, 1e-15);
      EXPECT_NEAR(v[3 * n + 2], 0.005, 1e-15);
    }
  }
  // One frame: the top moves up, the bottom stays in its plane, both slide freely across.
  ASSERT_TRUE(scene.integrator->advance(s, 0.02).ok);
  for (int n = 0; n < 9; ++n) EXPECT_EQ(s.state.x[3 * n + 2], 0.0);
  for (int n = 18; n < 27; ++n) EXPECT_NEAR(s.state.x[3 * n + 2], 0.0201, 1e-15);
}

TEST(BoundaryTags, IndexFileTagsEachAxis) {
  writeScene("node_tags.txt",
             "# node tags: x y z fix, X Y Z control\n"
             "0 xyz\n"
             "1 xy   # slides along z\n"
             "\n"
             "26 xyZ\n"
             "25 Xz\n"
             "24 Z\n");
  const std::string boundary = "{tags: {file: node_tags.txt, velocity: [0.002, 0, 0.001]}}";
  Scene scene = loadScene(writeScene("tag_file.yaml", replaced(kScene, "BOUNDARY", boundary)));
  System& s = scene.system;
  const std::set<int> expected = {0, 1, 2, 3, 4, 78, 79, 80, 75, 77, 74};
  EXPECT_EQ(constrained(s), expected);
  ASSERT_EQ(s.controlled.size(), 2u);  // the controlled axes x and z
  Eigen::VectorXd x = s.state.x, v = s.state.v;
  x.setConstant(7.0);
  s.prescribe(1.0, x, v);
  EXPECT_EQ(x.segment<3>(0), s.mesh.rest.col(0));
  EXPECT_EQ(x[5], 7.0);  // node 1: z free
  EXPECT_NEAR(x[3 * 26 + 2], 0.02 + 0.001, 1e-15);
  EXPECT_EQ(x[3 * 26], 0.02);
  EXPECT_NEAR(x[3 * 25], 0.01 + 0.002, 1e-15);
  EXPECT_EQ(x[3 * 25 + 1], 7.0);
  EXPECT_EQ(x[3 * 25 + 2], 0.02);
  EXPECT_NEAR(x[3 * 24 + 2], 0.02 + 0.001, 1e-15);
  EXPECT_EQ(x[3 * 24], 7.0);
}

// The nodes of `jaw: true` entries, and only those, are the scene's jaw nodes: fixed on all
// axes, sorted and each once when two jaw entries overlap.
TEST(BoundaryTags, JawEntriesListTheirNodes) {
  const std::string boundary = R"(
  fixed:
    - {nodes: [5, 2], jaw: true}
    - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}
    - {nodes: [2, 26], jaw: true}
    - {nodes: [24], jaw: false}
)";
  Scene scene = loadScene(writeScene("jaw_tags.yaml", replaced(kScene, "BOUNDARY", boundary)));
  EXPECT_EQ(scene.jawNodes, (std::vector<int>{2, 5, 26}));
  const std::set<int> fixed = constrained(scene.system);
  for (int n : {2, 5, 26, 24, 0})
    for (int d = 0; d < 3; ++d) EXPECT_EQ(fixed.count(3 * n + d), 1u) << n;
  EXPECT_EQ(fixed.size(), 3u * 11);  // the 9 nodes of z = 0 (2 and 5 among them), 24 and 26
  Scene plain = loadScene(writeScene("no_jaw_tags.yaml", replaced(kScene, "BOUNDARY", "{fixed: [{nodes: [3]}]}")));
  EXPECT_TRUE(plain.jawNodes.empty());
}

TEST(BoundaryTags, ReaderKeepsLinesAndLetters) {
  const std::string path = writeScene("reader_tags.txt", "3 zX\n3 y\n");
  const std::vector<NodeTagLine> lines = readNodeTagFile(path, 4);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].node, 3);
  EXPECT_EQ(lines[0].fixed, kFixedZ);
  EXPECT_EQ(lines[0].controlled, kFixedX);
  EXPECT_EQ(lines[1].fixed, kFixedY);
  EXPECT_EQ(lines[1].line, 2);
}

}  // namespace
}  // namespace tt
