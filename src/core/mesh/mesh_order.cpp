#include "tissue_trainer/core/mesh/mesh_order.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

namespace tt {
namespace {

// The node graph in compressed rows: the neighbours of node n are
// adjacent[start[n]] .. adjacent[start[n + 1] - 1], in increasing order.
struct NodeGraph {
  std::vector<int> start, adjacent;
  int degree(int n) const { return start[n + 1] - start[n]; }
};

template <class Element>
void addPairs(const std::vector<Element>& elements, std::vector<std::pair<int, int>>& pairs) {
  for (const Element& e : elements)
    for (int a : e)
      for (int b : e)
        if (a != b) pairs.emplace_back(a, b);
}

NodeGraph nodeGraph(const Mesh& mesh) {
  std::vector<std::pair<int, int>> pairs;
  addPairs(mesh.tets, pairs);
  addPairs(mesh.hexes, pairs);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  NodeGraph g;
  g.start.assign(mesh.numNodes() + 1, 0);
  for (const auto& p : pairs) ++g.start[p.first + 1];
  std::partial_sum(g.start.begin(), g.start.end(), g.start.begin());
  g.adjacent.reserve(pairs.size());
  for (const auto& p : pairs) g.adjacent.push_back(p.second);
  return g;
}

// Breadth-first levels from root: the nodes reached, the start of the last level in them and
// the number of levels. `seen` holds the stamp of the search that last reached each node.
struct Levels {
  std::vector<int> nodes;
  size_t lastLevel = 0;
  int depth = 0;
};

Levels levelsFrom(const NodeGraph& g, int root, std::vector<int>& seen, int stamp) {
  Levels l;
  l.nodes.push_back(root);
  seen[root] = stamp;
  for (size_t begin = 0; begin < l.nodes.size(); ++l.depth) {
    const size_t end = l.nodes.size();
    l.lastLevel = begin;
    for (size_t k = begin; k < end; ++k)
      for (int i = g.start[l.nodes[k]]; i < g.start[l.nodes[k] + 1]; ++i)
        if (seen[g.adjacent[i]] != stamp) {
          seen[g.adjacent[i]] = stamp;
          l.nodes.push_back(g.adjacent[i]);
        }
    begin = end;
  }
  return l;
}

// George-Liu: from `node`, move to a node of least degree in the last level while that
// lengthens the level structure.
int pseudoPeripheralNode(const NodeGraph& g, int node, std::vector<int>& seen, int& stamp) {
  Levels l = levelsFrom(g, node, seen, ++stamp);
  for (;;) {
    const auto last = std::min_element(
        l.nodes.begin() + l.lastLevel, l.nodes.end(),
        [&g](int a, int b) { return g.degree(a) < g.degree(b); });
    Levels next = levelsFrom(g, *last, seen, ++stamp);
    if (next.depth <= l.depth) return node;
    node = *last;
    l = std::move(next);
  }
}

std::uint64_t spreadBits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

std::vector<int> inverse(const std::vector<int>& p) {
  std::vector<int> inv(p.size());
  for (size_t i = 0; i < p.size(); ++i) inv[p[i]] = static_cast<int>(i);
  return inv;
}

void requirePermutation(const std::vector<int>& p, size_t size, const char* what) {
  std::vector<char> hit(size, 0);
  bool ok = p.size() == size;
  for (size_t i = 0; ok && i < p.size(); ++i) {
    ok = p[i] >= 0 && static_cast<size_t>(p[i]) < size && !hit[p[i]];
    if (ok) hit[p[i]] = 1;
  }
  if (!ok)
    throw std::invalid_argument(std::string("applyOrder: ") + what + " is not a permutation of " +
                                std::to_string(size));
}

template <class T>
void permute(std::vector<T>& values, const std::vector<int>& newIndex) {
  if (values.size() != newIndex.size()) return;  // absent: filled in by defaults
  std::vector<T> moved(values.size());
  for (size_t i = 0; i < values.size(); ++i) moved[newIndex[i]] = std::move(values[i]);
  values = std::move(moved);
}

template <class Element>
void relabel(std::vector<Element>& elements, const std::vector<int>& newNode) {
  for (Element& e : elements)
    for (int& a : e) a = newNode[a];
}

// File numbers after a renumbering by newIndex of items whose file numbers were toFile(i).
template <class ToFile>
void composeNumbering(const std::vector<int>& newIndex, ToFile toFile, std::vector<int>& file,
                      std::vector<int>& mesh) {
  std::vector<int> composed(newIndex.size());
  for (size_t i = 0; i < newIndex.size(); ++i) composed[newIndex[i]] = toFile(static_cast<int>(i));
  mesh = inverse(composed);
  file = std::move(composed);
}

}  // namespace

std::vector<int> reverseCuthillMcKee(const Mesh& mesh) {
  const NodeGraph g = nodeGraph(mesh);
  const int n = mesh.numNodes();
  std::vector<int> order, seen(n, 0);
  std::vector<char> placed(n, 0);
  order.reserve(n);
  int stamp = 0;
  std::vector<int> neighbours;
  for (int first = 0; first < n; ++first) {
    if (placed[first]) continue;
    const int root = pseudoPeripheralNode(g, first, seen, stamp);
    order.push_back(root);
    placed[root] = 1;
    for (size_t head = order.size() - 1; head < order.size(); ++head) {
      const int a = order[head];
      neighbours.clear();
      for (int i = g.start[a]; i < g.start[a + 1]; ++i)
        if (!placed[g.adjacent[i]]) {
          placed[g.adjacent[i]] = 1;
          neighbours.push_back(g.adjacent[i]);
        }
      std::stable_sort(neighbours.begin(), neighbours.end(),
                       [&g](int p, int q) { return g.degree(p) < g.degree(q); });
      order.insert(order.end(), neighbours.begin(), neighbours.end());
    }
  }
  std::reverse(order.begin(), order.end());
  return order;
}

std::vector<int> mortonNodeOrder(const Mesh& mesh) {
  const Box box = boundingBox(mesh.rest);
  const Eigen::Vector3d extent = (box.max - box.min).cwiseMax(1e-300);
  std::vector<std::uint64_t> key(mesh.numNodes());
  for (int n = 0; n < mesh.numNodes(); ++n) {
    const Eigen::Vector3d u = (mesh.rest.col(n) - box.min).cwiseQuotient(extent) * 2097151.0;
    key[n] = spreadBits(static_cast<std::uint64_t>(u.x())) |
             spreadBits(static_cast<std::uint64_t>(u.y())) << 1 |
             spreadBits(static_cast<std::uint64_t>(u.z())) << 2;
  }
  std::vector<int> order(mesh.numNodes());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&key](int a, int b) { return key[a] < key[b]; });
  return order;
}

MeshOrder localityOrder(const Mesh& mesh, NodeOrdering ordering) {
  MeshOrder o;
  o.newNode.resize(mesh.numNodes());
  o.newTet.resize(mesh.numTets());
  std::iota(o.newNode.begin(), o.newNode.end(), 0);
  std::iota(o.newTet.begin(), o.newTet.end(), 0);
  if (ordering == NodeOrdering::kFile) return o;
  o.newNode = inverse(ordering == NodeOrdering::kMorton ? mortonNodeOrder(mesh)
                                                        : reverseCuthillMcKee(mesh));
  std::vector<Tet> key(mesh.numTets());
  for (int t = 0; t < mesh.numTets(); ++t) {
    for (int i = 0; i < 4; ++i) key[t][i] = o.newNode[mesh.tets[t][i]];
    std::sort(key[t].begin(), key[t].end());
  }
  std::vector<int> tets(mesh.numTets());
  std::iota(tets.begin(), tets.end(), 0);
  std::stable_sort(tets.begin(), tets.end(), [&key](int a, int b) { return key[a] < key[b]; });
  o.newTet = inverse(tets);
  return o;
}

void applyOrder(Mesh& mesh, const MeshOrder& order) {
  requirePermutation(order.newNode, mesh.numNodes(), "the node order");
  requirePermutation(order.newTet, mesh.numTets(), "the tet order");
  Eigen::Matrix3Xd rest(3, mesh.numNodes());
  for (int n = 0; n < mesh.numNodes(); ++n) rest.col(order.newNode[n]) = mesh.rest.col(n);
  mesh.rest = std::move(rest);
  permute(mesh.nodeTags, order.newNode);
  relabel(mesh.tets, order.newNode);
  relabel(mesh.hexes, order.newNode);
  relabel(mesh.surface, order.newNode);
  permute(mesh.tets, order.newTet);
  permute(mesh.fibreFrame, order.newTet);
  permute(mesh.material, order.newTet);
  FileNumbering& f = mesh.numbering;
  composeNumbering(order.newNode, [&f](int n) { return f.nodeToFile(n); }, f.fileNode, f.meshNode);
  composeNumbering(order.newTet, [&f](int t) { return f.tetToFile(t); }, f.fileTet, f.meshTet);
}

Eigen::VectorXd nodeValuesFromFile(const FileNumbering& numbering, const Eigen::VectorXd& values) {
  Eigen::VectorXd out(values.size());
  for (Eigen::Index n = 0; n < values.size() / 3; ++n)
    out.segment<3>(3 * n) = values.segment<3>(3 * numbering.nodeToFile(static_cast<int>(n)));
  return out;
}

Eigen::VectorXd nodeValuesToFile(const FileNumbering& numbering, const Eigen::VectorXd& values) {
  Eigen::VectorXd out(values.size());
  for (Eigen::Index n = 0; n < values.size() / 3; ++n)
    out.segment<3>(3 * numbering.nodeToFile(static_cast<int>(n))) = values.segment<3>(3 * n);
  return out;
}

int nodeBandwidth(const Mesh& mesh) {
  int width = 0;
  const auto widen = [&width](const auto& element) {
    const auto [lo, hi] = std::minmax_element(element.begin(), element.end());
    width = std::max(width, *hi - *lo);
  };
  for (const Tet& t : mesh.tets) widen(t);
  for (const Hex& h : mesh.hexes) widen(h);
  return width;
}

}  // namespace tt
