#include "tissue_trainer/core/mesh/embedding.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tt {
namespace {

// A point counts as inside a tet when no barycentric coordinate is below -kInsideTolerance.
constexpr double kInsideTolerance = 1e-10;

// Barycentric coordinates (of a, b, c) of the point of triangle abc closest to p, found by
// testing which Voronoi region of the triangle (vertex, edge or face) contains p.
Eigen::Vector3d closestPointInTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c, const Eigen::Vector3d& p) {
  const Eigen::Vector3d ab = b - a, ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {1.0, 0.0, 0.0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {0.0, 1.0, 0.0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {1.0 - v, v, 0.0};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 0.0, 1.0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {1.0 - w, 0.0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0.0, 1.0 - w, w};
  }
  const double scale = 1.0 / (va + vb + vc);
  const double v = vb * scale, w = vc * scale;
  return {1.0 - v - w, v, w};
}

// Uniform grid of buckets over the mesh's bounding box; bucket `cell` lists every tet whose
// bounding box overlaps it (compressed row storage).
class TetGrid {
 public:
  explicit TetGrid(const Mesh& mesh) {
    const Box box = boundingBox(mesh.rest);
    origin_ = box.min;
    const Eigen::Vector3d extent = box.max - box.min;
    const double volume = std::max(extent.prod(), std::pow(extent.maxCoeff(), 3) * 1e-6);
    // About eight cells per tet: fewer candidates per query for a modest bucket memory.
    const double target = 0.5 * std::cbrt(volume / std::max(1, mesh.numTets()));
    for (int a = 0; a < 3; ++a) {
      dims_[a] = target > 0.0 ? std::clamp(static_cast<int>(std::ceil(extent[a] / target)), 1, 512)
                              : 1;
      cell_[a] = extent[a] / dims_[a];
    }
    start_.assign(static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2] + 1, 0);
    forEachTetCell(mesh, [&](int, int cell) { ++start_[cell + 1]; });
    for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    tets_.resize(start_.back());
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    forEachTetCell(mesh, [&](int t, int cell) { tets_[fill[cell]++] = t; });
  }

  std::array<int, 3> cellOf(const Eigen::Vector3d& p) const {
    std::array<int, 3> c;
    for (int a = 0; a < 3; ++a) {
      // Clamped as a double first: a far point must not overflow the int conversion.
      double i = cell_[a] > 0.0 ? std::floor((p[a] - origin_[a]) / cell_[a]) : 0.0;
      if (std::isnan(i)) i = 0.0;
      c[a] = static_cast<int>(std::clamp(i, 0.0, dims_[a] - 1.0));
    }
    return c;
  }
  int linear(int i, int j, int k) const { return i + dims_[0] * (j + dims_[1] * k); }
  const int* begin(int cell) const { return tets_.data() + start_[cell]; }
  const int* end(int cell) const { return tets_.data() + start_[cell + 1]; }
  int dim(int a) const { return dims_[a]; }
  // A lower bound on the distance from p (in cell c) to every cell farther than k from c in
  // Chebyshev distance: the distance to the nearest side of the block of cells within k that
  // has cells beyond it.
  double reachAfterShell(const Eigen::Vector3d& p, const std::array<int, 3>& c, int k) const {
    double reach = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      if (c[a] - k > 0) reach = std::min(reach, p[a] - (origin_[a] + (c[a] - k) * cell_[a]));
      if (c[a] + k < dims_[a] - 1)
        reach = std::min(reach, origin_[a] + (c[a] + k + 1) * cell_[a] - p[a]);
    }
    return std::max(reach, 0.0);
  }

 private:
  template <class F>
  void forEachTetCell(const Mesh& mesh, F&& f) const {
    for (int t = 0; t < mesh.numTets(); ++t) {
      Eigen::Vector3d lo = mesh.rest.col(mesh.tets[t][0]), hi = lo;
      for (int p = 1; p < 4; ++p) {
        lo = lo.cwiseMin(mesh.rest.col(mesh.tets[t][p]));
        hi = hi.cwiseMax(mesh.rest.col(mesh.tets[t][p]));
      }
      const std::array<int, 3> a = cellOf(lo), b = cellOf(hi);
      for (int k = a[2]; k <= b[2]; ++k)
        for (int j = a[1]; j <= b[1]; ++j)
          for (int i = a[0]; i <= b[0]; ++i) f(t, linear(i, j, k));
    }
  }

  Eigen::Vector3d origin_;
  double cell_[3];
  int dims_[3];
  std::vector<int> start_, tets_;
};

double sq(double x) { return x * x; }

struct Placement {
  int tet = -1;
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();
  double distance = 0.0;  // 0 when inside
  long tetsTested = 0;
};

Eigen::Vector4d barycentricOf(const Mesh& mesh, int t, const Eigen::Vector3d& p) {
  const Tet& n = mesh.tets[t];
  return barycentric(mesh.rest.col(n[0]), mesh.rest.col(n[1]), mesh.rest.col(n[2]),
                     mesh.rest.col(n[3]), p);
}

// The tet containing p among those bucketed with p's cell, preferring the one p is deepest in.
Placement findContaining(const Mesh& mesh, const TetGrid& grid, const Eigen::Vector3d& p) {
  Placement best;
  double deepest = -std::numeric_limits<double>::infinity();
  const std::array<int, 3> c = grid.cellOf(p);
  const int cell = grid.linear(c[0], c[1], c[2]);
  best.tetsTested = grid.end(cell) - grid.begin(cell);
  for (const int* t = grid.begin(cell); t != grid.end(cell); ++t) {
    const Eigen::Vector4d w = barycentricOf(mesh, *t, p);
    if (w.minCoeff() > deepest) {
      deepest = w.minCoeff();
      best.tet = *t;
      best.weights = w;
    }
  }
  if (deepest < -kInsideTolerance) best.tet = -1;
  return best;
}

// The tet nearest to p, searching shells of cells outwards from p's cell.
Placement findNearest(const Mesh& mesh, const TetGrid& grid, const Eigen::Vector3d& p,
                      std::vector<int>& visitedBy, int query) {
  Placement best;
  double bestSquared = std::numeric_limits<double>::infinity();
  const std::array<int, 3> c = grid.cellOf(p);
  const int maxShell = std::max({grid.dim(0), grid.dim(1), grid.dim(2)});
  for (int k = 0; k <= maxShell; ++k) {
    for (int z = std::max(0, c[2] - k); z <= std::min(grid.dim(2) - 1, c[2] + k); ++z)
      for (int y = std::max(0, c[1] - k); y <= std::min(grid.dim(1) - 1, c[1] + k); ++y)
        for (int x = std::max(0, c[0] - k); x <= std::min(grid.dim(0) - 1, c[0] + k); ++x) {
          const bool onShell = std::abs(x - c[0]) == k || std::abs(y - c[1]) == k ||
                               std::abs(z - c[2]) == k;
          if (!onShell) continue;
          const int cell = grid.linear(x, y, z);
          for (const int* t = grid.begin(cell); t != grid.end(cell); ++t) {
            if (visitedBy[*t] == query) continue;
            visitedBy[*t] = query;
            ++best.tetsTested;
            const Tet& n = mesh.tets[*t];
            Eigen::Vector4d w;
            const double d2 = closestPointInTet(mesh.rest.col(n[0]), mesh.rest.col(n[1]),
                                                mesh.rest.col(n[2]), mesh.rest.col(n[3]), p, w);
            if (d2 < bestSquared) {
              bestSquared = d2;
              best.tet = *t;
              best.weights = w;
            }
          }
        }
    if (best.tet >= 0 && bestSquared <= sq(grid.reachAfterShell(p, c, k))) break;
  }
  best.distance = std::sqrt(bestSquared);
  return best;
}

}  // namespace

Eigen::Vector4d barycentric(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c, const Eigen::Vector3d& d,
                            const Eigen::Vector3d& p) {
  Eigen::Matrix3d edges;
  edges << b - a, c - a, d - a;
  const Eigen::Vector3d w = edges.partialPivLu().solve(p - a);
  return {1.0 - w.sum(), w[0], w[1], w[2]};
}

double closestPointInTet(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& c, const Eigen::Vector3d& d,
                         const Eigen::Vector3d& p, Eigen::Vector4d& closest) {
  closest = barycentric(a, b, c, d, p);
  if (closest.minCoeff() >= 0.0) return 0.0;
  // Outside: the closest point lies on one of the faces.
  const Eigen::Vector3d* v[4] = {&a, &b, &c, &d};
  static const int kFaces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  double bestSquared = std::numeric_limits<double>::infinity();
  for (const auto& f : kFaces) {
    const Eigen::Vector3d w = closestPointInTriangle(*v[f[0]], *v[f[1]], *v[f[2]], p);
    const Eigen::Vector3d q = w[0] * *v[f[0]] + w[1] * *v[f[1]] + w[2] * *v[f[2]];
    const double d2 = (p - q).squaredNorm();
    if (d2 < bestSquared) {
      bestSquared = d2;
      closest.setZero();
      for (int i = 0; i < 3; ++i) closest[f[i]] = w[i];
    }
  }
  return bestSquared;
}

Embedding::Embedding(const Mesh& mesh, const Eigen::Matrix3Xd& points, OutsidePolicy policy) {
  const int count = static_cast<int>(points.cols());
  nodes_.resize(count);
  tet_.resize(count);
  weights_.resize(count);
  if (count == 0) return;
  if (mesh.numTets() == 0) throw std::invalid_argument("Embedding: the mesh has no tets");
  const TetGrid grid(mesh);
  std::vector<int> visitedBy(mesh.numTets(), -1);
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d p = points.col(i);
    Placement place = findContaining(mesh, grid, p);
    tetsTested_ += place.tetsTested;
    if (place.tet < 0) {
      place = findNearest(mesh, grid, p, visitedBy, i);
      tetsTested_ += place.tetsTested;
      ++numOutside_;
      maxOutsideDistance_ = std::max(maxOutsideDistance_, place.distance);
      if (policy == OutsidePolicy::kExtrapolate) place.weights = barycentricOf(mesh, place.tet, p);
    }
    tet_[i] = place.tet;
    nodes_[i] = mesh.tets[place.tet];
    weights_[i] = place.weights;
  }
}

void Embedding::apply(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Matrix3Xd& out) const {
  out.resize(3, numPoints());
  for (int i = 0; i < numPoints(); ++i) {
    const Tet& n = nodes_[i];
    const Eigen::Vector4d& w = weights_[i];
    out.col(i) = w[0] * x.segment<3>(3 * n[0]) + w[1] * x.segment<3>(3 * n[1]) +
                 w[2] * x.segment<3>(3 * n[2]) + w[3] * x.segment<3>(3 * n[3]);
  }
}

Eigen::Matrix3Xd Embedding::apply(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  Eigen::Matrix3Xd out;
  apply(x, out);
  return out;
}

}  // namespace tt
