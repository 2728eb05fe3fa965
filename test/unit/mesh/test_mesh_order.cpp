// Node and tet orders for locality (mesh_order.h): bijections, a smaller bandwidth than a
// shuffled file's, and a reordered mesh that is the same body (volume, surface, elastic
// energy and forces) with its file numbers recorded.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/mesh/mesh_order.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace {

std::vector<int> shuffled(int n, unsigned seed) {
  std::vector<int> p(n);
  std::iota(p.begin(), p.end(), 0);
  std::shuffle(p.begin(), p.end(), std::mt19937(seed));
  return p;
}

// A 9 x 7 x 6 box grid as a mesh generator without locality would number it: nodes and tets
// shuffled, with per-tet materials and frames and per-node tags to follow them. The shuffled
// numbers are the "file" numbers (no numbering recorded).
Mesh shuffledBox() {
  Mesh mesh = boxGrid(9, 7, 6, Eigen::Vector3d(0.04, 0.03, 0.025), TetSplit::kFiveMirrored);
  for (int t = 0; t < mesh.numTets(); ++t) {
    mesh.material[t] = t % 3;
    mesh.fibreFrame[t] = Eigen::AngleAxisd(0.01 * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  }
  for (int n = 0; n < mesh.numNodes(); ++n) mesh.nodeTags[n] = n % 5 == 0 ? kFixedAll : 0;
  applyOrder(mesh, {shuffled(mesh.numNodes(), 7), shuffled(mesh.numTets(), 11)});
  mesh.numbering = {};
  return mesh;
}

bool isPermutation(std::vector<int> p) {
  std::sort(p.begin(), p.end());
  for (size_t i = 0; i < p.size(); ++i)
    if (p[i] != static_cast<int>(i)) return false;
  return true;
}

double totalVolume(const Mesh& mesh) {
  double v = 0.0;
  for (const Tet& t : mesh.tets) v += tetVolume(mesh.rest, t);
  return v;
}

double surfaceArea(const Mesh& mesh, const std::vector<Triangle>& surface) {
  double a = 0.0;
  for (const Triangle& t : surface)
    a += 0.5 * (mesh.rest.col(t[1]) - mesh.rest.col(t[0]))
                   .cross(mesh.rest.col(t[2]) - mesh.rest.col(t[0]))
                   .norm();
  return a;
}

const NodeOrdering kOrderings[] = {NodeOrdering::kReverseCuthillMcKee, NodeOrdering::kMorton};

TEST(MeshOrder, OrdersAreBijections) {
  const Mesh mesh = shuffledBox();
  for (NodeOrdering ordering : kOrderings) {
    const MeshOrder o = localityOrder(mesh, ordering);
    ASSERT_EQ(o.newNode.size(), static_cast<size_t>(mesh.numNodes()));
    ASSERT_EQ(o.newTet.size(), static_cast<size_t>(mesh.numTets()));
    EXPECT_TRUE(isPermutation(o.newNode));
    EXPECT_TRUE(isPermutation(o.newTet));
  }
  EXPECT_TRUE(isPermutation(reverseCuthillMcKee(mesh)));
  EXPECT_TRUE(isPermutation(mortonNodeOrder(mesh)));
}

TEST(MeshOrder, FileOrderingChangesNothing) {
  const Mesh mesh = shuffledBox();
  const MeshOrder o = localityOrder(mesh, NodeOrdering::kFile);
  std::vector<int> identity(mesh.numNodes());
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_EQ(o.newNode, identity);
  identity.resize(mesh.numTets());
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_EQ(o.newTet, identity);
}

TEST(MeshOrder, BandwidthOfAShuffledMeshDecreases) {
  const Mesh mesh = shuffledBox();
  const int before = nodeBandwidth(mesh);
  EXPECT_GT(before, mesh.numNodes() / 2);
  // A Morton curve keeps neighbours close but jumps at the cell boundaries of its octree;
  // RCM bounds the width by about a layer of the 9 x 7 x 6 grid (7 x 6 nodes and diagonals).
  Mesh morton = mesh, rcm = mesh;
  applyOrder(morton, localityOrder(morton, NodeOrdering::kMorton));
  applyOrder(rcm, localityOrder(rcm, NodeOrdering::kReverseCuthillMcKee));
  EXPECT_LT(nodeBandwidth(morton), before);
  EXPECT_LT(nodeBandwidth(rcm), before / 3);
  EXPECT_LE(nodeBandwidth(rcm), 2 * 7 * 6);
}

TEST(MeshOrder, TetsWalkTheNodesForward) {
  Mesh mesh = shuffledBox();
  applyOrder(mesh, localityOrder(mesh, NodeOrdering::kReverseCuthillMcKee));
  for (int t = 1; t < mesh.numTets(); ++t)
    EXPECT_LE(*std::min_element(mesh.tets[t - 1].begin(), mesh.tets[t - 1].end()),
              *std::min_element(mesh.tets[t].begin(), mesh.tets[t].end()));
}

TEST(MeshOrder, ReorderedMeshIsTheSameBody) {
  const Mesh file = shuffledBox();
  for (NodeOrdering ordering : kOrderings) {
    Mesh mesh = file;
    applyOrder(mesh, localityOrder(mesh, ordering));
    const FileNumbering& f = mesh.numbering;
    EXPECT_NEAR(totalVolume(mesh), totalVolume(file), 1e-15);
    EXPECT_NEAR(surfaceArea(mesh, mesh.surface), surfaceArea(file, file.surface), 1e-15);
    EXPECT_NEAR(surfaceArea(mesh, extractSurface(mesh)), surfaceArea(file, file.surface), 1e-15);
    for (int n = 0; n < mesh.numNodes(); ++n) {
      EXPECT_EQ(f.nodeFromFile(f.nodeToFile(n)), n);
      EXPECT_EQ(mesh.rest.col(n), file.rest.col(f.nodeToFile(n)));
      EXPECT_EQ(mesh.nodeTags[n], file.nodeTags[f.nodeToFile(n)]);
    }
    for (int t = 0; t < mesh.numTets(); ++t) {
      const int ft = f.tetToFile(t);
      EXPECT_EQ(f.tetFromFile(ft), t);
      for (int i = 0; i < 4; ++i) EXPECT_EQ(f.nodeToFile(mesh.tets[t][i]), file.tets[ft][i]);
      EXPECT_EQ(mesh.material[t], file.material[ft]);
      EXPECT_EQ(mesh.fibreFrame[t], file.fibreFrame[ft]);
    }
  }
}

TEST(MeshOrder, ElasticEnergyAndForcesAreTheSameUpToThePermutation) {
  const Mesh file = shuffledBox();
  Mesh mesh = file;
  applyOrder(mesh, localityOrder(mesh, NodeOrdering::kReverseCuthillMcKee));
  const std::vector<Material> materials{Material::isotropic(5e3, 0.45, 1000),
                                        Material::isotropic(8e3, 0.4, 1000),
                                        Material::isotropic(2e4, 0.3, 1000)};
  const System a(file, materials), b(mesh, materials);
  const EdgeLengthModel modelA(a.mesh, a.materials), modelB(b.mesh, b.materials);
  // A deformed state: a twist and a stretch plus a smooth bulge.
  Eigen::VectorXd xa(3 * file.numNodes());
  for (int n = 0; n < file.numNodes(); ++n) {
    const Eigen::Vector3d p = file.rest.col(n);
    xa.segment<3>(3 * n) = Eigen::AngleAxisd(8.0 * p.z(), Eigen::Vector3d::UnitZ()) *
                               Eigen::Vector3d(1.1 * p.x(), p.y(), 0.95 * p.z()) +
                           0.002 * std::sin(90.0 * p.x()) * Eigen::Vector3d::UnitY();
  }
  const Eigen::VectorXd xb = nodeValuesFromFile(mesh.numbering, xa);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(xa.size());
  Eigen::VectorXd fa = zero, fb = zero;
  const double ea = modelA.addForce(xa, zero, fa), eb = modelB.addForce(xb, zero, fb);
  ASSERT_GT(ea, 0.0);
  EXPECT_NEAR(eb, ea, 1e-12 * ea);
  EXPECT_LT((nodeValuesToFile(mesh.numbering, fb) - fa).cwiseAbs().maxCoeff(),
            1e-12 * fa.cwiseAbs().maxCoeff());
  EXPECT_EQ(nodeValuesToFile(mesh.numbering, xb), xa);
}

TEST(MeshOrder, SecondReorderingKeepsTheFileNumbers) {
  const Mesh file = shuffledBox();
  Mesh mesh = file;
  applyOrder(mesh, localityOrder(mesh, NodeOrdering::kMorton));
  applyOrder(mesh, localityOrder(mesh, NodeOrdering::kReverseCuthillMcKee));
  for (int n = 0; n < mesh.numNodes(); ++n)
    EXPECT_EQ(mesh.rest.col(n), file.rest.col(mesh.numbering.nodeToFile(n)));
  for (int t = 0; t < mesh.numTets(); ++t)
    for (int i = 0; i < 4; ++i)
      EXPECT_EQ(mesh.numbering.nodeToFile(mesh.tets[t][i]),
                file.tets[mesh.numbering.tetToFile(t)][i]);
}

TEST(MeshOrder, HexesAreRelabelledInPlace) {
  const Mesh file = boxGrid(4, 3, 3, Eigen::Vector3d::Ones(), TetSplit::kNone);
  Mesh mesh = file;
  applyOrder(mesh, {shuffled(mesh.numNodes(), 3), {}});
  ASSERT_EQ(mesh.numHexes(), file.numHexes());
  for (int h = 0; h < mesh.numHexes(); ++h)
    for (int i = 0; i < 8; ++i)
      EXPECT_EQ(mesh.numbering.nodeToFile(mesh.hexes[h][i]), file.hexes[h][i]);
}

TEST(MeshOrder, RejectsAnOrderThatIsNoPermutation) {
  Mesh mesh = shuffledBox();
  MeshOrder o = localityOrder(mesh, NodeOrdering::kMorton);
  o.newNode[0] = o.newNode[1];
  EXPECT_THROW(applyOrder(mesh, o), std::invalid_argument);
  o = localityOrder(mesh, NodeOrdering::kMorton);
  o.newTet.pop_back();
  EXPECT_THROW(applyOrder(mesh, o), std::invalid_argument);
}

}  // namespace
}  // namespace tt
