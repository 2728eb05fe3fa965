#include "tissue_trainer/core/model/collision.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace tt {
namespace {

constexpr int kLeafSize = 4;
constexpr int kMaxStack = 128;  // a median-split tree of 2^60 triangles is 60 levels deep

double boxDistance2(const Eigen::Vector3d& x, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d d = (lo - x).cwiseMax(x - hi).cwiseMax(0.0);
  return d.squaredNorm();
}

Eigen::Matrix3d tangentProjector(const Eigen::Vector3d& n) {
  return Eigen::Matrix3d::Identity() - n * n.transpose();
}

}  // namespace

ClosedSurface::ClosedSurface(Eigen::Matrix3Xd vertices, std::vector<Triangle> triangles)
    : vertices_(std::move(vertices)), triangles_(std::move(triangles)) {
  const int nv = static_cast<int>(vertices_.cols());
  if (triangles_.empty()) throw std::invalid_argument("the surface has no triangles");
  double volume6 = 0.0;
  for (const Triangle& t : triangles_) {
    for (int v : t)
      if (v < 0 || v >= nv) throw std::invalid_argument("a triangle names a vertex outside the surface");
    volume6 += vertices_.col(t[0]).dot(vertices_.col(t[1]).cross(vertices_.col(t[2])));
  }
  if (volume6 < 0.0)
    for (Triangle& t : triangles_) std::swap(t[1], t[2]);

  const int nt = numTriangles();
  faceNormals_.resize(nt);
  vertexNormals_.assign(nv, Eigen::Vector3d::Zero());
  std::map<std::pair<int, int>, int> directed;  // (a, b) -> 3 t + k
  for (int t = 0; t < nt; ++t) {
    const Triangle& tri = triangles_[t];
    const Eigen::Vector3d n = (vertices_.col(tri[1]) - vertices_.col(tri[0]))
                                  .cross(vertices_.col(tri[2]) - vertices_.col(tri[0]));
    if (!(n.norm() > 0.0))
      throw std::invalid_argument("triangle " + std::to_string(t) + " has no area");
    faceNormals_[t] = n.normalized();
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3];
      if (!directed.emplace(std::make_pair(a, b), 3 * t + k).second)
        throw std::invalid_argument("edge (" + std::to_string(a) + ", " + std::to_string(b) +
                                    ") is traversed twice in one direction (a non-manifold or "
                                    "inconsistently oriented surface)");
      const Eigen::Vector3d u = vertices_.col(b) - vertices_.col(a);
      const Eigen::Vector3d w = vertices_.col(c) - vertices_.col(a);
      const double angle = std::atan2(u.cross(w).norm(), u.dot(w));
      vertexNormals_[a] += angle * faceNormals_[t];
    }
  }
  edgeNormals_.resize(3 * nt);
  for (const auto& [edge, slot] : directed) {
    const auto twin = directed.find({edge.second, edge.first});
    if (twin == directed.end())
      throw std::invalid_argument("edge (" + std::to_string(edge.first) + ", " +
                                  std::to_string(edge.second) +
                                  ") has one triangle (the surface is not closed)");
    edgeNormals_[slot] = faceNormals_[slot / 3] + faceNormals_[twin->second / 3];
  }

  order_.resize(nt);
  for (int t = 0; t < nt; ++t) order_[t] = t;
  nodes_.reserve(2 * nt / kLeafSize + 2);
  build(0, nt);
  lo_ = nodes_[0].lo;
  hi_ = nodes_[0].hi;
}

int ClosedSurface::build(int first, int count) {
  Node node;
  node.lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  node.hi = -node.lo;
  Eigen::Vector3d clo = node.lo, chi = node.hi;
  auto centroid = [&](int t) {
    const Triangle& tri = triangles_[t];
    return Eigen::Vector3d((vertices_.col(tri[0]) + vertices_.col(tri[1]) + vertices_.col(tri[2])) / 3.0);
  };
  for (int i = first; i < first + count; ++i) {
    for (int v : triangles_[order_[i]]) {
      node.lo = node.lo.cwiseMin(vertices_.col(v));
      node.hi = node.hi.cwiseMax(vertices_.col(v));
    }
    const Eigen::Vector3d c = centroid(order_[i]);
    clo = clo.cwiseMin(c);
    chi = chi.cwiseMax(c);
  }
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back(node);
  if (count <= kLeafSize) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  int axis;
  (chi - clo).maxCoeff(&axis);
  const int half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half,
                   order_.begin() + first + count,
                   [&](int a, int b) { return centroid(a)[axis] < centroid(b)[axis]; });
  const int left = build(first, half);
  const int right = build(first + half, count - half);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

// The nearest point of triangle t and the feature it lies on ("Real-Time Collision Detection",
// 2005, Sec. 5.1.5, by Voronoi regions).
ClosedSurface::Nearest ClosedSurface::nearestOnTriangle(const Eigen::Vector3d& x, int t) const {
  const Triangle& tri = triangles_[t];
  const Eigen::Vector3d a = vertices_.col(tri[0]), b = vertices_.col(tri[1]), c = vertices_.col(tri[2]);
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = x - a;
  auto result = [&](const Eigen::Vector3d& p, Feature f) {
    return Nearest{p, (x - p).squaredNorm(), t, f};
  };
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return result(a, kVertex0);
  const Eigen::Vector3d bp = x - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return result(b, kVertex1);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return result(a + d1 / (d1 - d3) * ab, kEdge0);
  const Eigen::Vector3d cp = x - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return result(c, kVertex2);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return result(a + d2 / (d2 - d6) * ac, kEdge2);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
    return result(b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b), kEdge1);
  const double denom = 1.0 / (va + vb + vc);
  return result(a + ab * (vb * denom) + ac * (vc * denom), kFace);
}

ClosedSurface::Nearest ClosedSurface::nearest(const Eigen::Vector3d& x) const {
  Nearest best{x, std::numeric_limits<double>::infinity(), -1, kFace};
  int stack[kMaxStack];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (boxDistance2(x, node.lo, node.hi) >= best.distance2) continue;
    if (node.left < 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const Nearest candidate = nearestOnTriangle(x, order_[i]);
        if (candidate.distance2 < best.distance2) best = candidate;
      }
      continue;
    }
    const double dl = boxDistance2(x, nodes_[node.left].lo, nodes_[node.left].hi);
    const double dr = boxDistance2(x, nodes_[node.right].lo, nodes_[node.right].hi);
    // The nearer child is popped first.
    stack[top++] = dl < dr ? node.right : node.left;
    stack[top++] = dl < dr ? node.left : node.right;
  }
  return best;
}

Eigen::Vector3d ClosedSurface::pseudoNormal(const Nearest& n) const {
  const Triangle& tri = triangles_[n.triangle];
  switch (n.feature) {
    case kFace: return faceNormals_[n.triangle];
    case kEdge0: case kEdge1: case kEdge2: return edgeNormals_[3 * n.triangle + (n.feature - kEdge0)];
    default: return vertexNormals_[tri[n.feature - kVertex0]];
  }
}

double ClosedSurface::signedDistance(const Eigen::Vector3d& x, Eigen::Vector3d& nearestPoint) const {
  const Nearest n = nearest(x);
  nearestPoint = n.point;
  const double d = std::sqrt(n.distance2);
  return (x - n.point).dot(pseudoNormal(n)) < 0.0 ? -d : d;
}

bool ClosedSurface::inside(const Eigen::Vector3d& x, Penetration& out) const {
  if ((x.array() <= lo_.array()).any() || (x.array() >= hi_.array()).any()) return false;
  const Nearest n = nearest(x);
  if (!((x - n.point).dot(pseudoNormal(n)) < 0.0)) return false;
  out.point = n.point;
  const Triangle& tri = triangles_[n.triangle];
  if (n.feature == kFace) {
    out.pointJacobian = tangentProjector(faceNormals_[n.triangle]);
  } else if (n.feature <= kEdge2) {
    const int k = n.feature - kEdge0;
    const Eigen::Vector3d t =
        (vertices_.col(tri[(k + 1) % 3]) - vertices_.col(tri[k])).normalized();
    out.pointJacobian = t * t.transpose();
  } else {
    out.pointJacobian.setZero();
  }
  return true;
}

CollisionBody CollisionBody::plane(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  if (!(normal.norm() > 0.0)) throw std::invalid_argument("a plane with a zero normal");
  CollisionBody b;
  b.kind = Kind::kPlane;
  b.point = point;
  b.normal = normal.normalized();
  return b;
}

CollisionBody CollisionBody::sphere(const Eigen::Vector3d& centre, double radius) {
  if (!(radius > 0.0)) throw std::invalid_argument("a sphere with a radius <= 0");
  CollisionBody b;
  b.kind = Kind::kSphere;
  b.point = centre;
  b.radius = radius;
  return b;
}

CollisionModel::CollisionModel(int numNodes, std::vector<int> nodes, double stiffness,
                               std::vector<CollisionBody> bodies,
                               std::vector<ClosedSurface> surfaces, bool psdProjection)
    : nodes_(std::move(nodes)),
      stiffness_(stiffness),
      bodies_(std::move(bodies)),
      surfaces_(std::move(surfaces)),
      psdProjection_(psdProjection) {
  if (!(stiffness_ > 0.0)) throw std::invalid_argument("collision: a stiffness <= 0");
  for (int n : nodes_)
    if (n < 0 || n >= numNodes)
      throw std::invalid_argument("collision: node " + std::to_string(n) + " is not in the mesh");
  for (const CollisionBody& b : bodies_)
    if (b.kind == CollisionBody::Kind::kMesh &&
        (b.surface < 0 || b.surface >= static_cast<int>(surfaces_.size())))
      throw std::invalid_argument("collision: a mesh body without its surface");
}

bool CollisionModel::penetration(const CollisionBody& b, const Eigen::Vector3d& x,
                                 Penetration& out) const {
  switch (b.kind) {
    case CollisionBody::Kind::kPlane: {
      const double s = (x - b.point).dot(b.normal);
      if (!(s < 0.0)) return false;
      out.point = x - s * b.normal;
      out.pointJacobian = tangentProjector(b.normal);
      return true;
    }
    case CollisionBody::Kind::kSphere: {
      const Eigen::Vector3d r = x - b.point;
      const double distance = r.norm();
      if (!(distance < b.radius)) return false;
      // At the centre every direction is nearest; +z is taken.
      const Eigen::Vector3d n = distance > 0.0 ? Eigen::Vector3d(r / distance) : Eigen::Vector3d::UnitZ();
      out.point = b.point + b.radius * n;
      const double curvature = psdProjection_ || !(distance > 0.0) ? 1.0 : b.radius / distance;
      out.pointJacobian = curvature * tangentProjector(n);
      return true;
    }
    case CollisionBody::Kind::kMesh:
      return surfaces_[b.surface].inside(x, out);
  }
  return false;
}

template <class Visit>
void CollisionModel::forEachContact(const Eigen::VectorXd& x, const Visit& visit) const {
  Penetration p;
  for (int node : nodes_) {
    const Eigen::Vector3d xi = x.segment<3>(3 * node);
    for (const CollisionBody& b : bodies_)
      if (penetration(b, xi, p)) visit(node, xi, p);
  }
}

double CollisionModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                Eigen::VectorXd& f) const {
  double e = 0.0;
  forEachContact(x, [&](int node, const Eigen::Vector3d& xi, const Penetration& p) {
    const Eigen::Vector3d push = p.point - xi;
    f.segment<3>(3 * node) += stiffness_ * push;
    e += 0.5 * stiffness_ * push.squaredNorm();
  });
  return e;
}

double CollisionModel::energy(const Eigen::VectorXd& x) const {
  double e = 0.0;
  forEachContact(x, [&](int, const Eigen::Vector3d& xi, const Penetration& p) {
    e += 0.5 * stiffness_ * (p.point - xi).squaredNorm();
  });
  return e;
}

void CollisionModel::addStiffness(const Eigen::VectorXd& x, double scale,
                                  const SparsePattern& pattern, SparseMatrix& K) const {
  forEachContact(x, [&](int node, const Eigen::Vector3d&, const Penetration& p) {
    pattern.addNodeBlock(K, node, node,
                         (scale * stiffness_) * (p.pointJacobian - Eigen::Matrix3d::Identity()));
  });
}

void CollisionModel::addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d,
                                       double scale, Eigen::VectorXd& out) const {
  forEachContact(x, [&](int node, const Eigen::Vector3d&, const Penetration& p) {
    out.segment<3>(3 * node) += (scale * stiffness_) *
                                (p.pointJacobian * d.segment<3>(3 * node) - d.segment<3>(3 * node));
  });
}

}  // namespace tt
