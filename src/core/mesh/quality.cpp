#include "tissue_trainer/core/mesh/quality.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <unordered_map>

#include "tissue_trainer/core/element/hex8.h"

namespace tt {

namespace {

constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

double longestEdge(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Tet& t) {
  double longest = 0.0;
  for (const auto& e : kTetEdges)
    longest = std::max(longest, (x.col(t[e[1]]) - x.col(t[e[0]])).norm());
  return longest;
}

double faceAreaSum(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Tet& t) {
  static const int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  double sum = 0.0;
  for (const auto& f : kFaces) {
    const Eigen::Vector3d a = x.col(t[f[0]]), b = x.col(t[f[1]]), c = x.col(t[f[2]]);
    sum += 0.5 * (b - a).cross(c - a).norm();
  }
  return sum;
}

// Number of nodes having an earlier node within tol: a hash grid of cell size >= tol, so
// only the 27 neighbouring cells need checking.
int countDuplicates(const Eigen::Ref<const Eigen::Matrix3Xd>& x, double tol) {
  const int n = static_cast<int>(x.cols());
  if (n < 2) return 0;
  const Box box = boundingBox(x);
  const double diagonal = (box.max - box.min).norm();
  if (!std::isfinite(diagonal)) return 0;
  if (diagonal == 0.0) return n - 1;
  const double h = std::max(tol, diagonal * 1e-12);
  auto cellOf = [&](int i) {
    Eigen::Matrix<std::int64_t, 3, 1> c;
    for (int k = 0; k < 3; ++k)
      c[k] = static_cast<std::int64_t>(std::floor((x(k, i) - box.min[k]) / h));
    return c;
  };
  auto key = [](std::int64_t a, std::int64_t b, std::int64_t c) {
    std::uint64_t k = static_cast<std::uint64_t>(a) * 0x9E3779B97F4A7C15ull;
    k ^= static_cast<std::uint64_t>(b) * 0xC2B2AE3D27D4EB4Full + (k << 6) + (k >> 2);
    k ^= static_cast<std::uint64_t>(c) * 0x165667B19E3779F9ull + (k << 6) + (k >> 2);
    return k;
  };
  std::unordered_multimap<std::uint64_t, int> grid;
  grid.reserve(static_cast<std::size_t>(n));
  int duplicates = 0;
  for (int i = 0; i < n; ++i) {
    const auto c = cellOf(i);
    bool found = false;
    for (int dx = -1; dx <= 1 && !found; ++dx)
      for (int dy = -1; dy <= 1 && !found; ++dy)
        for (int dz = -1; dz <= 1 && !found; ++dz) {
          const auto range = grid.equal_range(key(c[0] + dx, c[1] + dy, c[2] + dz));
          for (auto it = range.first; it != range.second && !found; ++it)
            found = (x.col(it->second) - x.col(i)).norm() <= tol;
        }
    if (found) ++duplicates;
    grid.emplace(key(c[0], c[1], c[2]), i);
  }
  return duplicates;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  const double upper = values[mid];
  if (values.size() % 2) return upper;
  return 0.5 * (upper + *std::max_element(values.begin(), values.begin() + mid));
}

}  // namespace

double tetNormalisedVolume(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Tet& t) {
  const double lmax = longestEdge(x, t);
  if (lmax == 0.0) return 0.0;
  return 6.0 * std::sqrt(2.0) * std::abs(tetVolume(x, t)) / (lmax * lmax * lmax);
}

double tetAspectRatio(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Tet& t) {
  const double volume = std::abs(tetVolume(x, t));
  const double areas = faceAreaSum(x, t);
  if (volume == 0.0 || areas == 0.0) return std::numeric_limits<double>::infinity();
  const double inradius = 3.0 * volume / areas;
  return longestEdge(x, t) / (2.0 * std::sqrt(6.0) * inradius);
}

double hexVolume(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Hex& h) {
  // Reference corners (xi, eta, zeta) in VTK/Gmsh hexahedron order.
  static const double kCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                       {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const double g = 1.0 / std::sqrt(3.0);
  double volume = 0.0;
  for (int q = 0; q < 8; ++q) {
    const double p[3] = {kCorner[q][0] * g, kCorner[q][1] * g, kCorner[q][2] * g};
    Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 8; ++i) {
      const double* c = kCorner[i];
      const Eigen::Vector3d dN(c[0] * (1 + c[1] * p[1]) * (1 + c[2] * p[2]) / 8.0,
                               c[1] * (1 + c[0] * p[0]) * (1 + c[2] * p[2]) / 8.0,
                               c[2] * (1 + c[0] * p[0]) * (1 + c[1] * p[1]) / 8.0);
      J += x.col(h[i]) * dN.transpose();
    }
    volume += J.determinant();  // Gauss weights are all 1
  }
  return volume;
}

MeshQuality meshQuality(const Mesh& mesh, const QualityOptions& options) {
  MeshQuality q;
  q.nodes = mesh.numNodes();
  q.tets = mesh.numTets();
  q.hexes = static_cast<int>(mesh.hexes.size());
  q.surfaceTriangles = static_cast<int>(mesh.surface.size());
  q.box = boundingBox(mesh.rest);

  std::vector<double> aspects;
  aspects.reserve(mesh.tets.size());
  double vmin = std::numeric_limits<double>::infinity(), vmax = -vmin;
  auto addVolume = [&](double v) {
    vmin = std::min(vmin, v);
    vmax = std::max(vmax, v);
    q.volumeTotal += v;
  };
  for (const Tet& t : mesh.tets) {
    const double v = tetVolume(mesh.rest, t);
    addVolume(v);
    aspects.push_back(tetAspectRatio(mesh.rest, t));
    const bool degenerate = !(tetNormalisedVolume(mesh.rest, t) >= options.degenerateVolume);
    if (degenerate) ++q.degenerate;
    else if (v < 0.0) ++q.inverted;
  }
  // A hex is checked through the six tets of its split: one flat or inverted tet makes the
  // hex degenerate or inverted, even when its total volume is positive (a twisted hex).
  for (const Hex& h : mesh.hexes) {
    addVolume(hexVolume(mesh.rest, h));
    bool degenerate = false, inverted = false;
    for (int k = 0; k < 6; ++k) {
      const Tet t = Hex8::sixTet(h, k);
      degenerate = degenerate || !(tetNormalisedVolume(mesh.rest, t) >= options.degenerateVolume);
      inverted = inverted || tetVolume(mesh.rest, t) < 0.0;
    }
    if (degenerate) ++q.degenerate;
    else if (inverted) ++q.inverted;
  }
  if (!mesh.tets.empty() || !mesh.hexes.empty()) {
    q.volumeMin = vmin;
    q.volumeMax = vmax;
  }
  if (!aspects.empty()) {
    q.aspectMin = *std::min_element(aspects.begin(), aspects.end());
    q.aspectMax = *std::max_element(aspects.begin(), aspects.end());
    q.aspectMedian = median(aspects);
  }

  const double diagonal = (q.box.max - q.box.min).norm();
  const double tol = options.duplicateTolerance > 0.0 ? options.duplicateTolerance : 1e-9 * diagonal;
  q.duplicateNodes = countDuplicates(mesh.rest, tol);

  q.unusedNodes = static_cast<int>(unusedNodes(mesh).size());
  return q;
}

std::vector<int> unusedNodes(const Mesh& mesh) {
  std::vector<char> used(static_cast<std::size_t>(mesh.numNodes()), 0);
  for (const Tet& t : mesh.tets)
    for (int v : t) used[v] = 1;
  for (const Hex& h : mesh.hexes)
    for (int v : h) used[v] = 1;
  std::vector<int> unused;
  for (int node = 0; node < mesh.numNodes(); ++node)
    if (!used[node]) unused.push_back(node);
  return unused;
}

std::vector<int> flatTets(const Mesh& mesh) {
  std::vector<int> flat;
  for (int t = 0; t < mesh.numTets(); ++t)
    if (!(tetNormalisedVolume(mesh.rest, mesh.tets[t]) >= kFlatTetVolume)) flat.push_back(t);
  return flat;
}

void removeTets(Mesh& mesh, const std::vector<int>& tets) {
  std::vector<char> removed(mesh.tets.size(), 0);
  for (int t : tets) removed[t] = 1;
  const auto keep = [&removed](auto& perTet) {
    if (perTet.size() != removed.size()) return;  // absent (filled in later by defaults)
    std::size_t kept = 0;
    for (std::size_t t = 0; t < perTet.size(); ++t)
      if (!removed[t]) perTet[kept++] = perTet[t];
    perTet.resize(kept);
  };
  keep(mesh.fibreFrame);
  keep(mesh.material);
  keep(mesh.tets);
}

double shortestEdge(const Mesh& mesh) {
  static constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  static constexpr int kHexEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                           {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  double shortest = std::numeric_limits<double>::infinity();
  const auto edge = [&](int a, int b) {
    shortest = std::min(shortest, (mesh.rest.col(a) - mesh.rest.col(b)).norm());
  };
  for (const Tet& t : mesh.tets)
    for (const auto& e : kTetEdges) edge(t[e[0]], t[e[1]]);
  for (const Hex& h : mesh.hexes)
    for (const auto& e : kHexEdges) edge(h[e[0]], h[e[1]]);
  return shortest;
}

std::string formatQuality(const MeshQuality& q) {
  char buf[1024];
  std::string out;
  std::snprintf(buf, sizeof buf, "nodes %d, tets %d, hexes %d, surface triangles %d\n", q.nodes,
                q.tets, q.hexes, q.surfaceTriangles);
  out += buf;
  const Eigen::Vector3d size = q.box.max - q.box.min;
  std::snprintf(buf, sizeof buf,
                "bounding box [%.6g, %.6g, %.6g] to [%.6g, %.6g, %.6g] (size %.6g x %.6g x %.6g)\n",
                q.box.min.x(), q.box.min.y(), q.box.min.z(), q.box.max.x(), q.box.max.y(),
                q.box.max.z(), size.x(), size.y(), size.z());
  out += buf;
  std::snprintf(buf, sizeof buf, "volume total %.6g, per element min %.6g max %.6g\n",
                q.volumeTotal, q.volumeMin, q.volumeMax);
  out += buf;
  std::snprintf(buf, sizeof buf,
                "tet aspect ratio (longest edge / (2 sqrt6 inradius), 1 = regular) min %.4g "
                "median %.4g max %.4g\n",
                q.aspectMin, q.aspectMedian, q.aspectMax);
  out += buf;
  std::snprintf(buf, sizeof buf,
                "inverted %d, degenerate %d, duplicate nodes %d, unused nodes %d\n", q.inverted,
                q.degenerate, q.duplicateNodes, q.unusedNodes);
  out += buf;
  return out;
}

int repairInverted(Mesh& mesh) {
  int fixed = 0;
  for (Tet& t : mesh.tets)
    if (tetVolume(mesh.rest, t) < 0.0) {
      std::swap(t[1], t[2]);
      ++fixed;
    }
  return fixed;
}

}  // namespace tt
