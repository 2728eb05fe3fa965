// Malformed boundary tags: each bad line of an index file of "node tags" and each bad key of a
// controlled entry or of boundary.tags is one InputError naming the file and the line.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_util.h"
#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/mesh/node_tags.h"

namespace tt {
namespace {

using testutil::BadScene;
using testutil::replaced;
using testutil::writeScene;

TEST(MalformedNodeTags, EachBadLineIsOneLineNamingFileAndLine) {
  const std::vector<BadScene> cases = {
      {"three tokens", "0 xyz\n1 x y\n", 2, "expected 'node tags' such as '12 xy' or '40 xyZ' (2 values), got 3 values"},
      {"node alone", "# tags\n\n5\n", 3, "expected 'node tags'"},
      {"unknown letter", "0 xyz\n1 xw\n", 2, "unknown tag 'w' (expected x, y, z to fix an axis and X, Y, Z to control it)"},
      {"fixed and controlled", "2 xX\n", 1, "an axis both fixed and controlled in 'xX'"},
      {"fixed, then controlled", "2 xy\n3 Z\n2 Y\n", 3,
       "node 2 has an axis fixed on one line and controlled on another"},
      {"controlled, then fixed", "4 Z # driven\n\n4 z\n", 3,
       "node 4 has an axis fixed on one line and controlled on another"},
      {"node out of range", "0 x\n8 z\n", 2, "expected a node index in [0, 7]"},
      {"negative node", "-1 z\n", 1, "expected a node index in [0, 7]"},
      {"not an integer", "1.5 z\n", 1, "expected a node index (an integer), got '1.5'"},
  };
  testutil::expectEachFileFailsClearly(
      cases, "bad_tags.txt", [](const std::string& path) { readNodeTagFile(path, 8); });
}

// Line numbers refer to this text (27 nodes).
const char* const kBoundaryTagScene = R"(mesh: {generator: box, nodes: [3, 3, 3], size: [0.02, 0.02, 0.02]}
materials: [{young_modulus: 3000, poisson_ratio: 0.3}]
force_models: [{type: edge_length}]
integrator: {type: backward_euler}
boundary:
  BOUNDARY
)";

TEST(MalformedNodeTags, SceneKeysNameFileLineAndKey) {
  writeScene("controls.txt", "26 Z\n");
  writeScene("fixes.txt", "0 xyz\n");
  writeScene("out_of_range.txt", "0 xyz\n27 z\n");
  const auto with = [](const std::string& b) { return replaced(kBoundaryTagScene, "BOUNDARY", b); };
  const std::vector<BadScene> cases = {
      {"no motion", with("controlled: [{nodes: [26], axes: z}]"), 6,
       "boundary.controlled[0]: expected one of 'path', 'velocity' or 'step'"},
      {"two motions", with("controlled: [{nodes: [26], velocity: [0, 0, 1], step: [0, 0, 1]}]"), 6,
       "expected only one of 'path', 'velocity' or 'step'"},
      {"motion along a free axis", with("controlled: [{nodes: [26], axes: z, velocity: [0.1, 0, 1]}]"), 6,
       "boundary.controlled[0].velocity: expected no motion along x, which the entry does not control"},
      {"path along a free axis", with("controlled: [{nodes: [26], axes: xy, path: [[0, 0, 0, 0], [1, 0, 0, 0.1]]}]"), 6,
       "boundary.controlled[0].path[1]: expected no motion along z"},
      {"bad axes", with("controlled: [{nodes: [26], axes: w, velocity: [0, 0, 1]}]"), 6,
       "boundary.controlled[0].axes: expected a combination of x, y and z"},
      {"tag file missing", with("tags: {file: no_such_tags.txt}"), 6, "boundary.tags.file: tag file"},
      {"controls without motion", with("tags: {file: controls.txt}"), 6,
       "boundary.tags: expected one of 'path', 'velocity' or 'step' for the controlled axes"},
      {"motion along an axis no tag controls", with("tags: {file: controls.txt, velocity: [0.1, 0, 1]}"), 6,
       "boundary.tags.velocity: expected no motion along x, which the entry does not control"},
      {"motion without controls", with("tags: {file: fixes.txt, velocity: [0, 0, 1]}"), 6,
       "boundary.tags: the tag file controls no node (X, Y, Z), so nothing reads the motion"},
      {"unknown tags key", with("tags: {file: fixes.txt, speed: 1}"), 6,
       "boundary.tags.speed: unknown key 'speed'"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_boundary.yaml");
}

// `jaw: true` marks fixed nodes that a landmark fit's jaw moves: on all axes only, a boolean.
TEST(MalformedNodeTags, JawEntriesFixAllAxesAndTakeABoolean) {
  const auto with = [](const std::string& b) { return replaced(kBoundaryTagScene, "BOUNDARY", b); };
  const std::vector<BadScene> cases = {
      {"jaw on some axes", with("fixed: [{nodes: [0, 1], axes: xy, jaw: true}]"), 6,
       "boundary.fixed[0].axes: expected xyz for a jaw entry: the jaw moves its nodes on all axes"},
      {"jaw not a boolean", with("fixed: [{nodes: [0, 1], jaw: 1}]"), 6,
       "boundary.fixed[0].jaw: expected true or false, got '1'"},
      {"jaw misspelt", with("fixed: [{nodes: [0, 1], jaws: true}]"), 6,
       "boundary.fixed[0].jaws: unknown key 'jaws'"},
      {"jaw on a controlled entry", with("controlled: [{nodes: [26], velocity: [0, 0, 1], jaw: true}]"), 6,
       "boundary.controlled[0].jaw: unknown key 'jaw'"},
  };
  testutil::expectEachSceneFailsClearly(cases, "bad_jaw.yaml");
}

// A node outside the mesh in the index file names the index file and its line.
TEST(MalformedNodeTags, OutOfRangeNodeIsRefused) {
  writeScene("out_of_range.txt", "0 xyz\n27 z\n");
  const std::string scene = writeScene("range.yaml", replaced(kBoundaryTagScene, "BOUNDARY", "tags: {file: out_of_range.txt}"));
  try {
    loadScene(scene);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(e.file().find("out_of_range.txt"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("expected a node index in [0, 26], got 27"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tt
