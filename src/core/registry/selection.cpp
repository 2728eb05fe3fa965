#include "tissue_trainer/core/registry/selection.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>

namespace tt {
namespace {

// Element e of the mesh numbered tets first, then hexes.
Eigen::Vector3d elementCentroid(const Mesh& mesh, int e) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  if (e < mesh.numTets()) {
    for (int a : mesh.tets[e]) c += 0.25 * mesh.rest.col(a);
  } else {
    for (int a : mesh.hexes[e - mesh.numTets()]) c += 0.125 * mesh.rest.col(a);
  }
  return c;
}

}  // namespace

int elementFromFile(const Mesh& mesh, int e) {
  return e < mesh.numTets() ? mesh.numbering.tetFromFile(e) : e;
}

int elementToFile(const Mesh& mesh, int e) {
  return e < mesh.numTets() ? mesh.numbering.tetToFile(e) : e;
}

std::vector<int> selectNodes(const YamlEntry& spec, const Mesh& mesh) {
  std::vector<int> nodes;
  const int n = mesh.numNodes();
  if (spec.has("box")) {
    const YamlEntry box = spec["box"];
    box.expectMap({"min", "max"});
    const Eigen::Vector3d lo = box["min"].vector3(), hi = box["max"].vector3();
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d p = mesh.rest.col(i);
      if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) nodes.push_back(i);
    }
  } else if (spec.has("plane")) {
    const YamlEntry plane = spec["plane"];
    plane.expectMap({"point", "normal", "tolerance"});
    const Eigen::Vector3d point = plane["point"].vector3();
    Eigen::Vector3d normal = plane["normal"].vector3();
    if (normal.norm() == 0.0) plane["normal"].fail("expected a non-zero normal");
    normal.normalize();
    const double tol = plane.positive("tolerance", 1e-9 * (mesh.rest.maxCoeff() - mesh.rest.minCoeff() + 1.0));
    for (int i = 0; i < n; ++i)
      if (std::abs((mesh.rest.col(i) - point).dot(normal)) <= tol) nodes.push_back(i);
  } else if (spec.has("nodes")) {
    const YamlEntry list = spec["nodes"];
    nodes = list.integers();
    for (size_t k = 0; k < nodes.size(); ++k)
      if (nodes[k] < 0 || nodes[k] >= n)
        list[k].fail("expected a node index in [0, " + std::to_string(n - 1) + "]");
    for (int& node : nodes) node = mesh.numbering.nodeFromFile(node);
  } else {
    spec.fail("expected one of 'box', 'plane' or 'nodes'");
  }
  if (nodes.empty()) spec.fail("the selection matches no node");
  return nodes;
}

std::vector<int> regionElements(const YamlEntry& region, const Mesh& mesh) {
  const int count = mesh.numTets() + mesh.numHexes();
  std::vector<int> elements;
  if (region.node().IsScalar()) {
    region.choice({"all"});
    for (int e = 0; e < count; ++e) elements.push_back(e);
    return elements;
  }
  region.expectMap({"box", "elements"});
  if (region.has("box") == region.has("elements"))
    region.fail("expected one of 'box' or 'elements'");
  if (region.has("elements")) {
    const YamlEntry list = region["elements"];
    elements = list.integers();
    for (size_t k = 0; k < elements.size(); ++k)
      if (elements[k] < 0 || elements[k] >= count)
        list[k].fail("expected an element index in [0, " + std::to_string(count - 1) + "]");
    if (elements.empty()) list.fail("expected at least one element index");
    for (int& e : elements) e = elementFromFile(mesh, e);
    std::sort(elements.begin(), elements.end());
    elements.erase(std::unique(elements.begin(), elements.end()), elements.end());
    return elements;
  }
  const YamlEntry box = region["box"];
  box.expectMap({"min", "max"});
  const Eigen::Vector3d lo = box["min"].vector3(), hi = box["max"].vector3();
  for (int e = 0; e < count; ++e) {
    const Eigen::Vector3d c = elementCentroid(mesh, e);
    if ((c.array() >= lo.array()).all() && (c.array() <= hi.array()).all()) elements.push_back(e);
  }
  if (elements.empty()) region.fail("the region contains no element");
  return elements;
}

}  // namespace tt
