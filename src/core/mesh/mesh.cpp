#include "tissue_trainer/core/mesh/mesh.h"

#include <Eigen/Dense>
#include <algorithm>
#include <map>

namespace tt {

void Mesh::fillDefaults() {
  if (fibreFrame.size() != tets.size()) fibreFrame.assign(tets.size(), Eigen::Matrix3d::Identity());
  if (material.size() != tets.size()) material.assign(tets.size(), 0);
  if (hexFibreFrame.size() != hexes.size())
    hexFibreFrame.assign(hexes.size(), Eigen::Matrix3d::Identity());
  if (hexMaterial.size() != hexes.size()) hexMaterial.assign(hexes.size(), 0);
  if (nodeTags.size() != static_cast<size_t>(numNodes())) nodeTags.assign(numNodes(), 0);
}

double tetVolume(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Tet& t) {
  Eigen::Matrix3d D;
  D << x.col(t[1]) - x.col(t[0]), x.col(t[2]) - x.col(t[0]), x.col(t[3]) - x.col(t[0]);
  return D.determinant() / 6.0;
}

std::vector<Triangle> extractSurface(const Mesh& mesh) {
  // Faces of a positively oriented tet (a,b,c,d) with outward normals.
  static const int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  std::map<std::array<int, 3>, std::pair<Triangle, int>> faces;
  for (const Tet& t : mesh.tets) {
    const bool positive = tetVolume(mesh.rest, t) >= 0.0;
    for (const auto& f : kFaces) {
      Triangle tri{t[f[0]], t[f[1]], t[f[2]]};
      if (!positive) std::swap(tri[1], tri[2]);
      std::array<int, 3> key = tri;
      std::sort(key.begin(), key.end());
      auto [it, inserted] = faces.emplace(key, std::make_pair(tri, 1));
      if (!inserted) ++it->second.second;
    }
  }
  std::vector<Triangle> surface;
  for (const auto& [key, value] : faces)
    if (value.second == 1) surface.push_back(value.first);
  // Hex faces (Hex8::faces, counter-clockwise from outside), each boundary quad as two
  // triangles (a, b, c) and (a, c, d).
  static const int kQuads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                   {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  std::map<std::array<int, 4>, std::pair<std::array<int, 4>, int>> quads;
  for (const Hex& h : mesh.hexes)
    for (const auto& q : kQuads) {
      const std::array<int, 4> quad{h[q[0]], h[q[1]], h[q[2]], h[q[3]]};
      std::array<int, 4> key = quad;
      std::sort(key.begin(), key.end());
      auto [it, inserted] = quads.emplace(key, std::make_pair(quad, 1));
      if (!inserted) ++it->second.second;
    }
  for (const auto& [key, value] : quads) {
    if (value.second != 1) continue;
    const std::array<int, 4>& q = value.first;
    surface.push_back({q[0], q[1], q[2]});
    surface.push_back({q[0], q[2], q[3]});
  }
  return surface;
}

Box boundingBox(const Eigen::Ref<const Eigen::Matrix3Xd>& x) {
  if (x.cols() == 0) return {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  return {x.rowwise().minCoeff(), x.rowwise().maxCoeff()};
}

}  // namespace tt
