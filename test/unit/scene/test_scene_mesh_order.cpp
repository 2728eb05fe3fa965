// A mesh file is reordered for locality when the scene loads it (mesh.node_order, default rcm;
// mesh_order.h), and everything that names its nodes or tets keeps the file's numbers: node and
// element selections, tag files, fibre files, landmark files. Loaded with node_order: rcm or
// morton, the scene is the same body as with node_order: file.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "scene_test_util.h"
#include "tissue_trainer/core/fit/landmark_fit.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/mesh/mesh_order.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

using testutil::replaced;
using testutil::writeScene;

// A 6 x 5 x 4 box grid (300 tets) with shuffled nodes and tets, as TetGen files beside the scenes.
void writeShuffledBox() {
  Mesh mesh = boxGrid(6, 5, 4, Eigen::Vector3d(0.05, 0.04, 0.03), TetSplit::kFiveMirrored);
  std::vector<int> nodes(mesh.numNodes()), tets(mesh.numTets());
  std::iota(nodes.begin(), nodes.end(), 0);
  std::iota(tets.begin(), tets.end(), 0);
  std::shuffle(nodes.begin(), nodes.end(), std::mt19937(5));
  std::shuffle(tets.begin(), tets.end(), std::mt19937(6));
  applyOrder(mesh, {nodes, tets});
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "tt_scene_tests";
  std::filesystem::create_directories(dir);
  writeTetgen((dir / "order_box").string(), mesh);
}

const char* const kScene = R"(mesh: {file: order_box.node, node_order: ORDER}
fibres: {file: order_fibres.txt}
materials:
  - {young_modulus: 3000, poisson_ratio: 0.3}
  - {region: {elements: [3, 17, 40, 299]}, young_modulus: 9000, poisson_ratio: 0.3}
force_models: [{type: edge_length}]
integrator: {type: backward_euler}
boundary:
  fixed: [{nodes: [0, 7, 93], axes: xy}]
  tags: {file: order_tags.txt}
)";

Scene loadOrdered(const std::string& order) {
  return loadScene(writeScene("order_" + order + ".yaml", replaced(kScene, "ORDER", order)));
}

class SceneMeshOrder : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    writeShuffledBox();
    std::string fibres;
    for (int e = 0; e < 300; ++e)
      fibres += std::to_string(e % 90) + " " + std::to_string((7 * e) % 90) + "\n";
    writeScene("order_fibres.txt", fibres);
    writeScene("order_tags.txt", "11 z\n12 xyz\n");
  }
};

Eigen::Vector3d fileNode(const Mesh& mesh, int n) {
  return mesh.rest.col(mesh.numbering.nodeFromFile(n));
}

TEST_F(SceneMeshOrder, ReorderingIsOnByDefaultForAMeshFile) {
  const Scene scene = loadScene(writeScene(
      "order_default.yaml", replaced(kScene, "file: order_box.node, node_order: ORDER",
                                     "file: order_box.node")));
  const Mesh& mesh = scene.system.mesh;
  ASSERT_EQ(mesh.numTets(), 300);
  EXPECT_FALSE(mesh.numbering.fileNode.empty());
  EXPECT_LT(nodeBandwidth(mesh), nodeBandwidth(loadOrdered("file").system.mesh) / 2);
}

TEST_F(SceneMeshOrder, FileNumbersKeepTheirMeaning) {
  const Scene file = loadOrdered("file");
  const Mesh& a = file.system.mesh;
  EXPECT_TRUE(a.numbering.fileNode.empty());
  for (const char* order : {"rcm", "morton"}) {
    const Scene scene = loadOrdered(order);
    const Mesh& b = scene.system.mesh;
    ASSERT_EQ(b.numNodes(), a.numNodes());
    for (int n = 0; n < a.numNodes(); ++n) {
      EXPECT_EQ(fileNode(b, n), a.rest.col(n)) << order << " node " << n;
      // Fixed axes from the `nodes` selection and the tag file.
      EXPECT_EQ(b.nodeTags[b.numbering.nodeFromFile(n)], a.nodeTags[n]) << order << " node " << n;
    }
    EXPECT_EQ(a.nodeTags[7], kFixedX | kFixedY);
    EXPECT_EQ(a.nodeTags[11], kFixedZ);
    for (int t = 0; t < a.numTets(); ++t) {
      const int bt = b.numbering.tetFromFile(t);
      for (int i = 0; i < 4; ++i) EXPECT_EQ(fileNode(b, a.tets[t][i]), b.rest.col(b.tets[bt][i]));
      EXPECT_EQ(b.material[bt], a.material[t]) << order << " tet " << t;
      EXPECT_TRUE(b.fibreFrame[bt].isApprox(a.fibreFrame[t], 1e-15)) << order << " tet " << t;
    }
    EXPECT_EQ(a.material[17], 1);
    EXPECT_EQ(a.material[299], 1);
    EXPECT_EQ(std::count(a.material.begin(), a.material.end(), 1), 4);
    EXPECT_EQ(scene.system.constrainedDofs.size(), file.system.constrainedDofs.size());
  }
}

TEST_F(SceneMeshOrder, LandmarksNameTheFilesNodesAndTets) {
  const std::string path = writeScene("order_landmarks.txt", "node 21 0 0 0\ntet 250 0.1 0.2 0.3 0.4 0 0 0\n");
  const Mesh a = loadOrdered("file").system.mesh, b = loadOrdered("rcm").system.mesh;
  const std::vector<Landmark> la = readLandmarks(path, a), lb = readLandmarks(path, b);
  ASSERT_EQ(la.size(), 2u);
  ASSERT_EQ(lb.size(), 2u);
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(b.rest.col(lb[k].nodes[i]), a.rest.col(la[k].nodes[i])) << k;
      EXPECT_EQ(lb[k].weights[i], la[k].weights[i]);
    }
}

TEST_F(SceneMeshOrder, ElasticEnergyIsTheSameInEveryOrder) {
  Scene file = loadOrdered("file"), rcm = loadOrdered("rcm");
  const Mesh& a = file.system.mesh;
  Eigen::VectorXd xa(3 * a.numNodes());
  for (int n = 0; n < a.numNodes(); ++n)
    xa.segment<3>(3 * n) = Eigen::AngleAxisd(5.0 * a.rest(2, n), Eigen::Vector3d::UnitZ()) *
                           a.rest.col(n).cwiseProduct(Eigen::Vector3d(1.1, 0.97, 1.02));
  const Eigen::VectorXd xb = nodeValuesFromFile(rcm.system.mesh.numbering, xa);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(xa.size());
  Eigen::VectorXd fa = zero, fb = zero;
  const double ea = file.system.models[0]->addForce(xa, zero, fa);
  const double eb = rcm.system.models[0]->addForce(xb, zero, fb);
  ASSERT_GT(ea, 0.0);
  EXPECT_NEAR(eb, ea, 1e-12 * ea);
  EXPECT_LT((nodeValuesToFile(rcm.system.mesh.numbering, fb) - fa).cwiseAbs().maxCoeff(),
            1e-12 * fa.cwiseAbs().maxCoeff());
}

TEST_F(SceneMeshOrder, GeneratedMeshesKeepTheGeneratorsOrder) {
  const Scene scene = loadScene(writeScene(
      "order_generated.yaml",
      "mesh: {generator: box, nodes: [3, 3, 3], size: [0.02, 0.02, 0.02]}\n"
      "materials: [{young_modulus: 3000, poisson_ratio: 0.3}]\n"
      "force_models: [{type: edge_length}]\n"
      "integrator: {type: backward_euler}\n"));
  EXPECT_TRUE(scene.system.mesh.numbering.fileNode.empty());
  EXPECT_TRUE(scene.system.mesh.numbering.fileTet.empty());
}

TEST_F(SceneMeshOrder, UnknownOrderIsAnErrorAtTheKey) {
  testutil::expectEachSceneFailsClearly(
      {{"unknown order", replaced(kScene, "ORDER", "hilbert"), 1, "node_order"}}, "order_bad.yaml");
}

}  // namespace
}  // namespace tt
