#include "tissue_trainer/core/model/adamss/cavity.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {
namespace adamss {
namespace {

std::string edgeName(int a, int b) {
  return "(" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) + ")";
}

Eigen::Matrix3d skew(const Eigen::Vector3d& u) {
  Eigen::Matrix3d s;
  s << 0, -u.z(), u.y(), u.z(), 0, -u.x(), -u.y(), u.x(), 0;
  return s;
}

}  // namespace

void checkClosedSurface(const std::vector<CavityFacet>& facets, int numNodes) {
  if (facets.empty()) throw std::invalid_argument("adamss_cavity: no facets");
  // Per undirected edge: how often it is run a -> b with a < b, and b -> a.
  std::map<std::pair<int, int>, std::array<int, 2>> edges;
  for (std::size_t f = 0; f < facets.size(); ++f) {
    const CavityFacet& facet = facets[f];
    const std::string which = "adamss_cavity: facet " + std::to_string(f);
    if (facet.size() != 3 && facet.size() != 4)
      throw std::invalid_argument(which + " has " + std::to_string(facet.size()) +
                                  " nodes (expected 3 or 4)");
    for (std::size_t i = 0; i < facet.size(); ++i) {
      if (facet[i] < 0 || facet[i] >= numNodes)
        throw std::invalid_argument(which + ": node " + std::to_string(facet[i]) +
                                    " is not in [0, " + std::to_string(numNodes - 1) + "]");
      for (std::size_t j = 0; j < i; ++j)
        if (facet[i] == facet[j])
          throw std::invalid_argument(which + " repeats node " + std::to_string(facet[i]));
    }
    for (std::size_t i = 0; i < facet.size(); ++i) {
      const int a = facet[i], b = facet[(i + 1) % facet.size()];
      ++edges[{std::min(a, b), std::max(a, b)}][a < b ? 0 : 1];
    }
  }
  for (const auto& [edge, count] : edges) {
    const std::string name = edgeName(edge.first, edge.second);
    if (count[0] + count[1] != 2)
      throw std::invalid_argument("adamss_cavity: edge " + name + " belongs to " +
                                  std::to_string(count[0] + count[1]) +
                                  " facets; a closed surface has every edge in exactly two");
    if (count[0] != 1)
      throw std::invalid_argument("adamss_cavity: the two facets at edge " + name +
                                  " run along it the same way; orient the facets consistently");
  }
}

double enclosedVolume(const std::vector<CavityFacet>& facets, const Eigen::Ref<const Eigen::Matrix3Xd>& x) {
  if (facets.empty()) return 0.0;
  // Relative to one of the surface's nodes: the same volume, less cancellation.
  const Eigen::Vector3d o = x.col(facets.front().front());
  const auto triple = [&](int a, int b, int c) {
    return (x.col(a) - o).dot((x.col(b) - o).cross(x.col(c) - o));
  };
  double v = 0.0;
  for (const CavityFacet& f : facets) {
    if (f.size() == 3)
      v += triple(f[0], f[1], f[2]);
    else
      v += 0.5 * (triple(f[0], f[1], f[2]) + triple(f[0], f[2], f[3]) +
                  triple(f[0], f[1], f[3]) + triple(f[1], f[2], f[3]));
  }
  return v / 6.0;
}

CavityModel::CavityModel(const Eigen::Matrix3Xd& rest, const std::vector<CavityFacet>& facets,
                         const CavityParameters& parameters)
    : pressure_(parameters.pressureFollowsCurve ? parameters.pressureCurve.value(0.0)
                                                 : parameters.pressure),
      parameters_(parameters) {
  const int n = static_cast<int>(rest.cols());
  checkClosedSurface(facets, n);
  for (const CavityFacet& facet : facets)
    nodes_.insert(nodes_.end(), facet.begin(), facet.end());
  std::sort(nodes_.begin(), nodes_.end());
  nodes_.erase(std::unique(nodes_.begin(), nodes_.end()), nodes_.end());
  origin_ = Eigen::Vector3d::Zero();
  for (int a : nodes_) origin_ += rest.col(a);
  origin_ /= static_cast<double>(nodes_.size());

  const auto local = [&](int node) {
    return static_cast<int>(std::lower_bound(nodes_.begin(), nodes_.end(), node) - nodes_.begin());
  };
  const auto add = [&](int a, int b, int c, double weight) {
    triangles_.push_back({{a, b, c}, {local(a), local(b), local(c)}, weight});
  };
  for (const CavityFacet& f : facets) {
    if (f.size() == 3) {
      add(f[0], f[1], f[2], 1.0);
    } else {
      add(f[0], f[1], f[2], 0.5);
      add(f[0], f[2], f[3], 0.5);
      add(f[0], f[1], f[3], 0.5);
      add(f[1], f[2], f[3], 0.5);
    }
  }
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(rest.data(), 3 * n);
  restVolume_ = volume(x);
  const Box box = boundingBox(rest);
  const double extent = (box.max - box.min).maxCoeff();
  if (!(std::abs(restVolume_) > 1e-12 * extent * extent * extent))
    throw std::invalid_argument("adamss_cavity: the facets enclose no volume");
  if (restVolume_ < 0.0) {
    for (Triangle& t : triangles_) {
      std::swap(t.node[1], t.node[2]);
      std::swap(t.local[1], t.local[2]);
    }
    restVolume_ = -restVolume_;
  }
  targetVolume_ = parameters_.targetVolumeRatio * restVolume_;
}

double CavityModel::volume(const Eigen::VectorXd& x) const {
  double v = 0.0;
  for (const Triangle& t : triangles_) {
    const Eigen::Vector3d a = x.segment<3>(3 * t.node[0]) - origin_;
    const Eigen::Vector3d b = x.segment<3>(3 * t.node[1]) - origin_;
    const Eigen::Vector3d c = x.segment<3>(3 * t.node[2]) - origin_;
    v += t.weight * a.dot(b.cross(c));
  }
  return v / 6.0;
}

void CavityModel::beginStep(double t, const Eigen::VectorXd& /*x*/,
                            const Eigen::VectorXd& /*v*/) {
  pressure_ = parameters_.pressureCurve.value(t);
}

double CavityModel::forceFactor(double volume) const {
  return pressure_ - parameters_.volumeStiffness * (volume - targetVolume_);
}

double CavityModel::energy(const Eigen::VectorXd& x) const {
  const double v = volume(x), dv = v - targetVolume_;
  return -pressure_ * v + 0.5 * parameters_.volumeStiffness * dv * dv;
}

double CavityModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& /*v*/,
                             Eigen::VectorXd& f) const {
  const double v = volume(x);
  const double scale = forceFactor(v) / 6.0;
  for (const Triangle& t : triangles_) {
    const Eigen::Vector3d a = x.segment<3>(3 * t.node[0]) - origin_;
    const Eigen::Vector3d b = x.segment<3>(3 * t.node[1]) - origin_;
    const Eigen::Vector3d c = x.segment<3>(3 * t.node[2]) - origin_;
    const double s = scale * t.weight;
    f.segment<3>(3 * t.node[0]) += s * b.cross(c);
    f.segment<3>(3 * t.node[1]) += s * c.cross(a);
    f.segment<3>(3 * t.node[2]) += s * a.cross(b);
  }
  const double dv = v - targetVolume_;
  return -pressure_ * v + 0.5 * parameters_.volumeStiffness * dv * dv;
}

Eigen::Matrix3Xd CavityModel::volumeGradient(const Eigen::VectorXd& x) const {
  Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(nodes_.size()));
  for (const Triangle& t : triangles_) {
    const Eigen::Vector3d a = x.segment<3>(3 * t.node[0]) - origin_;
    const Eigen::Vector3d b = x.segment<3>(3 * t.node[1]) - origin_;
    const Eigen::Vector3d c = x.segment<3>(3 * t.node[2]) - origin_;
    const double s = t.weight / 6.0;
    g.col(t.local[0]) += s * b.cross(c);
    g.col(t.local[1]) += s * c.cross(a);
    g.col(t.local[2]) += s * a.cross(b);
  }
  return g;
}

// d2V/dx_a dx_b of a triangle (a, b, c) in cyclic order is -[c]x / 6 (and its transpose for
// (b, a)); the diagonal blocks are zero.
void CavityModel::addStiffness(const Eigen::VectorXd& x, double scale,
                               const SparsePattern& pattern, SparseMatrix& K) const {
  const double v = volume(x);
  const double factor = scale * forceFactor(v);
  for (const Triangle& t : triangles_) {
    for (int i = 0; i < 3; ++i) {
      const int a = t.node[i], b = t.node[(i + 1) % 3], c = t.node[(i + 2) % 3];
      const Eigen::Matrix3d block =
          (-factor * t.weight / 6.0) * skew(x.segment<3>(3 * c) - origin_);
      pattern.addNodeBlock(K, a, b, block);
      pattern.addNodeBlock(K, b, a, block.transpose());
    }
  }
  if (parameters_.volumeStiffness == 0.0) return;
  const Eigen::Matrix3Xd g = volumeGradient(x);
  const double k = scale * parameters_.volumeStiffness;
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    for (std::size_t j = 0; j < nodes_.size(); ++j)
      pattern.addNodeBlock(K, nodes_[i], nodes_[j], -k * g.col(i) * g.col(j).transpose());
}

void CavityModel::addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d,
                                    double scale, Eigen::VectorXd& out) const {
  const double v = volume(x);
  const double factor = scale * forceFactor(v) / 6.0;
  double gradientDotD = 0.0;
  for (const Triangle& t : triangles_) {
    const Eigen::Vector3d a = x.segment<3>(3 * t.node[0]) - origin_;
    const Eigen::Vector3d b = x.segment<3>(3 * t.node[1]) - origin_;
    const Eigen::Vector3d c = x.segment<3>(3 * t.node[2]) - origin_;
    const Eigen::Vector3d da = d.segment<3>(3 * t.node[0]);
    const Eigen::Vector3d db = d.segment<3>(3 * t.node[1]);
    const Eigen::Vector3d dc = d.segment<3>(3 * t.node[2]);
    const double s = factor * t.weight;
    // The directional derivative of each node's b x c.
    out.segment<3>(3 * t.node[0]) += s * (db.cross(c) + b.cross(dc));
    out.segment<3>(3 * t.node[1]) += s * (dc.cross(a) + c.cross(da));
    out.segment<3>(3 * t.node[2]) += s * (da.cross(b) + a.cross(db));
    gradientDotD += t.weight * (da.dot(b.cross(c)) + db.dot(c.cross(a)) + dc.dot(a.cross(b)));
  }
  if (parameters_.volumeStiffness == 0.0) return;
  const double s = -scale * parameters_.volumeStiffness * gradientDotD / 36.0;
  for (const Triangle& t : triangles_) {
    const Eigen::Vector3d a = x.segment<3>(3 * t.node[0]) - origin_;
    const Eigen::Vector3d b = x.segment<3>(3 * t.node[1]) - origin_;
    const Eigen::Vector3d c = x.segment<3>(3 * t.node[2]) - origin_;
    out.segment<3>(3 * t.node[0]) += s * t.weight * b.cross(c);
    out.segment<3>(3 * t.node[1]) += s * t.weight * c.cross(a);
    out.segment<3>(3 * t.node[2]) += s * t.weight * a.cross(b);
  }
}

std::vector<std::array<int, 2>> CavityModel::couplings() const {
  std::vector<std::array<int, 2>> pairs;
  if (parameters_.volumeStiffness != 0.0) {
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      for (std::size_t j = i + 1; j < nodes_.size(); ++j) pairs.push_back({nodes_[i], nodes_[j]});
  } else {
    for (const Triangle& t : triangles_)
      for (int i = 0; i < 3; ++i)
        pairs.push_back({std::min(t.node[i], t.node[(i + 1) % 3]),
                         std::max(t.node[i], t.node[(i + 1) % 3])});
  }
  return pairs;
}

}  // namespace adamss
}  // namespace tt
