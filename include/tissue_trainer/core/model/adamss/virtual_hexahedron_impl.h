#pragma once
// The members of adamss::VirtualHexahedronModel (model/adamss/virtual_hexahedron.h). Only the
// laws' registration files include this header (through model/law_model_factory.h) and compile
// the model of their law once, with an explicit instantiation; every other file includes
// virtual_hexahedron.h and links that compiled model.
#include <string>

#include "tissue_trainer/core/element/point_stiffness.h"
#include "tissue_trainer/core/model/adamss/virtual_hexahedron.h"

namespace tt {
namespace adamss {

template <class Law>
VirtualHexahedronModel<Law>::VirtualHexahedronModel(const Mesh& mesh,
                                                    const std::vector<Constants>& constants,
                                                    const LawOptions& options,
                                                    DeformationGradientSource source,
                                                    PointForceDistribution distribution)
    : options_(options), source_(source), distribution_(distribution) {
  const AxisMesh axes = buildAxes(mesh);
  build(mesh, mesh.tets, axes.tetRest, mesh.material, constants, "tet", tets_,
        tetVirtualHexahedron);
  build(mesh, mesh.hexes, axes.hexRest, mesh.hexMaterial, constants, "hex", hexes_,
        hexVirtualHexahedron);
  for (const auto& r : hexes_.rest) nonConservativeHexes_ += isConservative(r) ? 0 : 1;
  for (const auto& r : tets_.rest) nonConservativeTets_ += isConservative(r) ? 0 : 1;
}

template <class Law>
double VirtualHexahedronModel<Law>::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                             Eigen::VectorXd& f) const {
  const double e = forces(tets_, x, f) + forces(hexes_, x, f);
  return hasEnergy() ? e : 0.0;
}

template <class Law>
double VirtualHexahedronModel<Law>::energy(const Eigen::VectorXd& x) const {
  return hasEnergy() ? energyOf(tets_, x) + energyOf(hexes_, x) : 0.0;
}

template <class Law>
void VirtualHexahedronModel<Law>::addStiffness(const Eigen::VectorXd& x, double scale,
                                               const SparsePattern& pattern,
                                               SparseMatrix& K) const {
  addElementStiffness(
      pattern, K, scale, static_cast<int>(tets_.nodes.size()),
      [&](int e) { return elementStiffness(tets_, x, e); }, hexes_.nodes,
      [&](int e) { return elementStiffness(hexes_, x, e); });
}

template <class Law>
void VirtualHexahedronModel<Law>::addStiffnessTimes(const Eigen::VectorXd& x,
                                                    const Eigen::VectorXd& d, double scale,
                                                    Eigen::VectorXd& out) const {
  product(tets_, x, d, scale, out);
  product(hexes_, x, d, scale, out);
}

template <class Law>
template <class Element, class RestOf>
void VirtualHexahedronModel<Law>::build(const Mesh& mesh,
                                        const std::vector<typename Element::Nodes>& elements,
                                        const std::vector<AxisRest<Element>>& axes,
                                        const std::vector<int>& materials,
                                        const std::vector<Constants>& constants,
                                        const char* kind, VirtualHexahedra<Element, Law>& set,
                                        RestOf restOf) {
  set.nodes = elements;
  set.rest.resize(elements.size());
  set.law.reserve(elements.size());
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const std::string element = std::string(kind) + " " + std::to_string(e);
    if (!restOf(mesh, elements[e], axes[e], distribution_, set.rest[e]))
      throw std::invalid_argument("virtual_hexahedron: " + element +
                                  " is flat or inverted at rest, or its axes span no volume");
    const Eigen::Matrix3d& B = set.rest[e].axes0;
    if (!shapeFunctions() && !(B.transpose() * B).isIdentity(1e-9))
      throw std::invalid_argument("virtual_hexahedron: " + element +
                                  ": the axis approximation needs orthogonal axes");
    // The axis approximation works in the axes' frame, where the law's frame is I.
    set.law.push_back(Law::parameters(constants.at(materials.at(e)),
                                      shapeFunctions() ? B : Eigen::Matrix3d::Identity()));
  }
}

template <class Law>
template <int N>
NodeMatrix<N> VirtualHexahedronModel<Law>::relativeNodes(const Eigen::VectorXd& x,
                                                         const std::array<int, N>& nodes) {
  NodeMatrix<N> xe = gatherNodes<N>(x, nodes);
  return xe.colwise() - xe.col(0);  // F and the axes are unchanged; no digits lost
}

template <class Law>
template <int N>
LawPoint VirtualHexahedronModel<Law>::pointOf(const NodeMatrix<N>& xe,
                                              const VirtualHexahedronRest<N>& r) const {
  if (shapeFunctions()) return lawPoint(xe * r.gradient.transpose(), options_);
  return lawPoint(axisDeformationGradient(xe * r.axisWeights, r.length0), options_);
}

template <class Law>
template <class Element>
double VirtualHexahedronModel<Law>::forces(const VirtualHexahedra<Element, Law>& set,
                                           const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  constexpr int N = Element::kNodes;
  return accumulateElementForces<N>(set.nodes, f, [&](int e, NodeMatrix<N>& fe) {
    const NodeMatrix<N> xe = relativeNodes<N>(x, set.nodes[e]);
    const VirtualHexahedronRest<N>& r = set.rest[e];
    const LawPoint point = pointOf<N>(xe, r);
    const Eigen::Matrix3d P = Law::stress(set.law[e], point.F);
    if (shapeFunctions()) {
      fe.noalias() = -P * r.lever;
    } else {
      // Eq. 2.74 corrected: column l of zeta diag(1/|zeta^0|) S is sum_k S_kl zeta_k/|zeta_k^0|.
      const Eigen::Matrix3d S = point.F.inverse() * P;
      const Eigen::Matrix3d pointForce = (xe * r.axisWeights) *
                                         r.length0.cwiseInverse().asDiagonal() * S *
                                         r.pointArea.asDiagonal();
      fe.noalias() = -pointForce * r.distributionWeights.transpose();
    }
    return r.volume * Law::energy(set.law[e], point.F);
  });
}

template <class Law>
template <class Element>
double VirtualHexahedronModel<Law>::energyOf(const VirtualHexahedra<Element, Law>& set,
                                             const Eigen::VectorXd& x) const {
  constexpr int N = Element::kNodes;
  return sumOverTets(static_cast<int>(set.nodes.size()), [&](int e) {
    const VirtualHexahedronRest<N>& r = set.rest[e];
    return r.volume *
           Law::energy(set.law[e], pointOf<N>(relativeNodes<N>(x, set.nodes[e]), r).F);
  });
}

template <class Law>
template <class Element>
Eigen::Matrix<double, 3 * Element::kNodes, 3 * Element::kNodes>
VirtualHexahedronModel<Law>::elementStiffness(const VirtualHexahedra<Element, Law>& set,
                                              const Eigen::VectorXd& x, int e) const {
  constexpr int N = Element::kNodes;
  const VirtualHexahedronRest<N>& r = set.rest[e];
  LawPoint point = pointOf<N>(relativeNodes<N>(x, set.nodes[e]), r);
  Eigen::Matrix<double, 3 * N, 3 * N> Ke = Eigen::Matrix<double, 3 * N, 3 * N>::Zero();
  subtractPointStiffness<N>(pointTangent<Law>(set.law[e], point, options_), r.lever, r.gradient,
                            1.0, Ke);
  return Ke;
}

template <class Law>
template <class Element>
void VirtualHexahedronModel<Law>::product(const VirtualHexahedra<Element, Law>& set,
                                          const Eigen::VectorXd& x, const Eigen::VectorXd& d,
                                          double scale, Eigen::VectorXd& out) const {
  constexpr int N = Element::kNodes;
  accumulateElementForces<N>(set.nodes, out, [&](int e, NodeMatrix<N>& fe) {
    const VirtualHexahedronRest<N>& r = set.rest[e];
    LawPoint point = pointOf<N>(relativeNodes<N>(x, set.nodes[e]), r);
    const Eigen::Matrix3d dF = gatherNodes<N>(d, set.nodes[e]) * r.gradient.transpose();
    Eigen::Matrix3d dP;
    if (options_.psdProjection) {
      const Matrix9d A = pointTangent<Law>(set.law[e], point, options_);
      Eigen::Map<Eigen::Matrix<double, 9, 1>>(dP.data()) =
          A * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dF.data());
    } else {
      dP = Law::stressDifferential(set.law[e], point.F, dF);
    }
    fe.noalias() = -scale * dP * r.lever;
    return 0.0;
  });
}

}  // namespace adamss
}  // namespace tt
