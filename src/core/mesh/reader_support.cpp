#include "reader_support.h"

#include <algorithm>

#include "tissue_trainer/core/mesh/quality.h"

namespace tt {
namespace meshio {

int NodeIds::add(const Scanner& s, long long id) {
  const int next = size();
  const auto [it, inserted] = index_.emplace(id, next);
  if (!inserted) s.fail("expected a new node id, node " + std::to_string(id) + " is defined twice");
  return next;
}

int NodeIds::find(const Scanner& s, long long id) const {
  const auto it = index_.find(id);
  if (it == index_.end()) s.fail("expected a defined node id, got unknown node " + std::to_string(id));
  return it->second;
}

std::string IgnoredElements::note() const {
  std::vector<std::pair<int, std::pair<std::string, long>>> entries(counts_.begin(), counts_.end());
  std::stable_sort(entries.begin(), entries.end(),
                   [](const auto& a, const auto& b) { return a.second.second > b.second.second; });
  std::string line = "ignored";
  for (std::size_t i = 0; i < entries.size(); ++i) {
    line += i ? ", " : " ";
    line += std::to_string(entries[i].second.second) + " " + entries[i].second.first + " (" +
            codeLabel_ + " " + std::to_string(entries[i].first) + ")";
  }
  return line;
}

int gmshNodesPerElement(int type) {
  static const int kNodes[] = {0,  2,  3, 4,  4,  8,  6,  5,  3,  6, 9,
                               10, 27, 18, 14, 1, 8, 20, 15, 13};
  return type >= 1 && type < static_cast<int>(sizeof kNodes / sizeof kNodes[0]) ? kNodes[type] : 0;
}

std::string gmshTypeName(int type) {
  switch (type) {
    case 1: return "lines";
    case 2: return "triangles";
    case 3: return "quadrangles";
    case 4: return "tetrahedra";
    case 5: return "hexahedra";
    case 6: return "prisms";
    case 7: return "pyramids";
    case 8: return "3-node lines";
    case 9: return "6-node triangles";
    case 10: return "9-node quadrangles";
    case 11: return "10-node tetrahedra";
    case 12: return "27-node hexahedra";
    case 15: return "points";
    case 16: return "8-node quadrangles";
    case 17: return "20-node hexahedra";
    default: return "elements";
  }
}

std::string vtkTypeName(int type) {
  switch (type) {
    case 1: return "vertices";
    case 2: return "poly-vertices";
    case 3: return "lines";
    case 4: return "poly-lines";
    case 5: return "triangles";
    case 6: return "triangle strips";
    case 7: return "polygons";
    case 8: return "pixels";
    case 9: return "quads";
    case 10: return "tetrahedra";
    case 11: return "voxels";
    case 12: return "hexahedra";
    case 13: return "wedges";
    case 14: return "pyramids";
    case 24: return "quadratic tetrahedra";
    case 25: return "quadratic hexahedra";
    default: return "cells";
  }
}

void addVtkCell(const Scanner& s, long line, std::size_t c, int type, const int* nodes, int k,
                Mesh& mesh, IgnoredElements& ignored) {
  // VTK voxel corners are ordered like a lexicographic grid; hexahedron corners are cyclic.
  static const int kVoxelToHex[8] = {0, 1, 3, 2, 4, 5, 7, 6};
  const bool tet = type == 10, hex = type == 12 || type == 11;
  if (!tet && !hex) {
    ignored.add(type, vtkTypeName(type));
    return;
  }
  const int expected = tet ? 4 : 8;
  if (k != expected)
    s.failAt(line, "expected " + std::to_string(expected) + " nodes for cell " + std::to_string(c) +
                       " of type " + std::to_string(type) + ", got " + std::to_string(k));
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < i; ++j)
      if (nodes[i] == nodes[j])
        s.failAt(line, "expected distinct nodes in cell " + std::to_string(c) + ", node " +
                           std::to_string(nodes[i]) + " is repeated");
  if (tet) {
    mesh.tets.push_back({nodes[0], nodes[1], nodes[2], nodes[3]});
  } else {
    Hex h;
    for (int j = 0; j < 8; ++j) h[j] = nodes[type == 11 ? kVoxelToHex[j] : j];
    mesh.hexes.push_back(h);
  }
}

Eigen::Matrix3Xd NodeBuffer::matrix() const {
  return Eigen::Map<const Eigen::Matrix3Xd>(xyz.data(), 3, static_cast<Eigen::Index>(xyz.size() / 3));
}

void addNote(ReadNotes* notes, const std::string& line) {
  if (notes) notes->lines.push_back(line);
}

void finishVolumeMesh(Mesh& mesh, const std::string& path, const IgnoredElements& ignored,
                      ReadNotes* notes) {
  if (mesh.tets.empty() && mesh.hexes.empty())
    throw InputError(path, 0, "expected at least one tetrahedron or hexahedron, found none" +
                                  (ignored.empty() ? std::string() : " (" + ignored.note() + ")"));
  if (!ignored.empty()) addNote(notes, ignored.note());
  const int reordered = repairInverted(mesh);
  if (reordered > 0)
    addNote(notes, "reordered " + std::to_string(reordered) +
                       " inverted tetrahedra to positive orientation");
  mesh.surface = extractSurface(mesh);
  mesh.fillDefaults();
}

}  // namespace meshio
}  // namespace tt
