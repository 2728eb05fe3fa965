#include "tissue_trainer/core/model/adamss/virtual_hexahedron.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace tt {
namespace adamss {
namespace {

// The equal-share coefficient matrix of Sec. 2.4.2.3: each point's force in equal parts to
// the nodes of the face holding it.
template <class Element>
PointCoefficients<Element::kNodes> equalShares(const AxisRest<Element>& axes) {
  PointCoefficients<Element::kNodes> C = PointCoefficients<Element::kNodes>::Zero();
  for (int j = 0; j < kAxisPoints; ++j)
    for (int node : Element::faces[axes.face[j]]) C(node, j) = 1.0 / Element::kFaceNodes;
  return C;
}

// Everything but the volume and the shape-function gradient, from the axes (Eqs. 2.57-2.58).
template <class Element>
bool fromAxes(const AxisRest<Element>& axes, PointForceDistribution distribution,
              VirtualHexahedronRest<Element::kNodes>& out) {
  const PointCoefficients<Element::kNodes> shares =
      distribution == PointForceDistribution::kAxes ? axes.C : equalShares(axes);
  for (int l = 0; l < kAxes; ++l) {
    out.axisWeights.col(l) = axes.C.col(2 * l) - axes.C.col(2 * l + 1);
    out.distributionWeights.col(l) = shares.col(2 * l) - shares.col(2 * l + 1);
  }
  out.length0 = axes.length0;
  out.axes0 = axes.axes0;
  const Eigen::Matrix3d zeta0 = axes.axes0 * axes.length0.asDiagonal();
  const double boxVolume = std::abs(zeta0.determinant());  // V_h
  if (!(boxVolume > 0.0) || !std::isfinite(boxVolume)) return false;
  const double volumeRatio = out.volume / boxVolume;  // R_v, Eq. 2.58
  // Column l: A_l n_l, the area times the outward normal of the box face through q_2l.
  Eigen::Matrix3d faceArea;
  for (int l = 0; l < kAxes; ++l) {
    const Eigen::Vector3d a = zeta0.col((l + 1) % 3).cross(zeta0.col((l + 2) % 3));
    faceArea.col(l) = a.dot(zeta0.col(l)) > 0.0 ? a : Eigen::Vector3d(-a);
    out.pointArea[l] = volumeRatio * a.norm();
  }
  out.lever = volumeRatio * faceArea * out.distributionWeights.transpose();
  return true;
}

}  // namespace

bool tetVirtualHexahedron(const Mesh& mesh, const Tet& nodes, const AxisRest<Tet4>& axes,
                          PointForceDistribution distribution,
                          VirtualHexahedronRest<Tet4::kNodes>& out) {
  const Tet4::Rest rest = Tet4::rest(mesh.rest, nodes);
  out.volume = rest.weight[0];
  out.gradient = rest.grad[0];
  return out.volume > 0.0 && fromAxes(axes, distribution, out);
}

bool hexVirtualHexahedron(const Mesh& mesh, const Hex& nodes, const AxisRest<Hex8>& axes,
                          PointForceDistribution distribution,
                          VirtualHexahedronRest<Hex8::kNodes>& out) {
  const Hex8::Rest rest = Hex8::rest(mesh.rest, nodes);
  if (!std::all_of(rest.weight.begin(), rest.weight.end(), [](double w) { return w > 0.0; }))
    return false;
  out.volume = 0.0;
  for (double w : rest.weight) out.volume += w;
  double detJ = 0.0;
  out.gradient = Hex8::gradientsAt(gatherNodes<Hex8::kNodes>(mesh.rest, nodes),
                                   Eigen::Vector3d::Zero(), &detJ);
  return detJ > 0.0 && fromAxes(axes, distribution, out);
}

Eigen::Matrix3d axisDeformationGradient(const Eigen::Matrix3d& zeta,
                                        const Eigen::Vector3d& length0) {
  const Eigen::Vector3d length = zeta.colwise().norm();
  Eigen::Matrix3d beta = Eigen::Matrix3d::Zero();  // Eq. 2.60
  for (int i = 0; i < kAxes; ++i)
    for (int j = i + 1; j < kAxes; ++j) {
      const double c = zeta.col(i).dot(zeta.col(j)) / (length[i] * length[j]);
      beta(i, j) = beta(j, i) = 0.5 * (0.5 * M_PI - std::acos(std::clamp(c, -1.0, 1.0)));
    }
  Eigen::Matrix3d F;
  for (int i = 0; i < kAxes; ++i) {
    double stretch = length[i] / length0[i];  // Eq. 2.61
    for (int j = 0; j < kAxes; ++j)
      if (j != i) stretch *= std::cos(beta(i, j));
    for (int j = 0; j < kAxes; ++j) F(i, j) = i == j ? stretch : stretch * std::tan(beta(i, j));
  }
  return F;
}

}  // namespace adamss
}  // namespace tt
