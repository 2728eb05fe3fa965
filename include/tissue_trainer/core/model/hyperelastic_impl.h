#pragma once
// The members of HyperelasticModel (model/hyperelastic.h). Only the laws' registration files
// include this header (through model/law_model_factory.h) and compile the model of their law
// once, with an explicit instantiation; every other file includes hyperelastic.h and links that
// compiled model instead of compiling the element loops again.
#include <cmath>
#include <stdexcept>
#include <string>

#include "tissue_trainer/core/element/point_stiffness.h"
#include "tissue_trainer/core/model/hyperelastic.h"

namespace tt {

template <class Element, class Law>
void LawElements<Element, Law>::build(const Mesh& mesh,
                                      const std::vector<typename Element::Nodes>& elements,
                                      const std::vector<Eigen::Matrix3d>& frames,
                                      const std::vector<int>& materials,
                                      const std::vector<typename Law::Constants>& constants,
                                      const char* kind) {
  nodes = elements;
  rest.reserve(elements.size());
  law.reserve(elements.size());
  for (std::size_t e = 0; e < elements.size(); ++e) {
    rest.push_back(Element::rest(mesh.rest, elements[e]));
    for (double w : rest.back().weight)
      if (!(w > 0.0))
        throw std::invalid_argument(std::string("hyperelastic: ") + kind + " " +
                                    std::to_string(e) + " is inverted or flat at rest");
    law.push_back(Law::parameters(constants.at(materials.at(e)), frames.at(e)));
  }
}

template <class Law>
HyperelasticModel<Law>::HyperelasticModel(const Mesh& mesh, const std::vector<Constants>& constants,
                                          const LawOptions& options)
    : options_(options) {
  tets_.build(mesh, mesh.tets, mesh.fibreFrame, mesh.material, constants, "tet");
  hexes_.build(mesh, mesh.hexes, mesh.hexFibreFrame, mesh.hexMaterial, constants, "hex");
}

template <class Law>
double HyperelasticModel<Law>::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                        Eigen::VectorXd& f) const {
  return forces(tets_, x, f) + forces(hexes_, x, f);
}

template <class Law>
double HyperelasticModel<Law>::energy(const Eigen::VectorXd& x) const {
  return energyOf(tets_, x) + energyOf(hexes_, x);
}

template <class Law>
void HyperelasticModel<Law>::addStiffness(const Eigen::VectorXd& x, double scale,
                                          const SparsePattern& pattern, SparseMatrix& K) const {
  addElementStiffness(
      pattern, K, scale, static_cast<int>(tets_.nodes.size()),
      [&](int e) { return elementStiffness(tets_, x, e); }, hexes_.nodes,
      [&](int e) { return elementStiffness(hexes_, x, e); });
}

template <class Law>
void HyperelasticModel<Law>::addStiffnessTimes(const Eigen::VectorXd& x,
                                               const Eigen::VectorXd& d, double scale,
                                               Eigen::VectorXd& out) const {
  product(tets_, x, d, scale, out);
  product(hexes_, x, d, scale, out);
}

template <class Law>
template <int N>
NodeMatrix<N> HyperelasticModel<Law>::relativeNodes(const Eigen::VectorXd& x,
                                                    const std::array<int, N>& nodes) {
  // Positions relative to node 0: the gradients of each point sum to zero, so F is the same
  // and a translated element loses no digits.
  NodeMatrix<N> xe = gatherNodes<N>(x, nodes);
  return xe.colwise() - xe.col(0);
}

template <class Law>
template <class Element>
double HyperelasticModel<Law>::forces(const LawElements<Element, Law>& set,
                                      const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  return accumulateElementForces<Element::kNodes>(
      set.nodes, f, [&](int e, NodeMatrix<Element::kNodes>& fe) {
        const NodeMatrix<Element::kNodes> xe = relativeNodes<Element::kNodes>(x, set.nodes[e]);
        const typename Element::Rest& r = set.rest[e];
        double energy = 0.0;
        fe.setZero();
        for (int q = 0; q < Element::kPoints; ++q) {
          const LawPoint point = lawPoint(xe * r.grad[q].transpose(), options_);
          energy += r.weight[q] * Law::energy(set.law[e], point.F);
          fe.noalias() -= (r.weight[q] * Law::stress(set.law[e], point.F)) * r.grad[q];
        }
        return energy;
      });
}

template <class Law>
template <class Element>
double HyperelasticModel<Law>::energyOf(const LawElements<Element, Law>& set,
                                        const Eigen::VectorXd& x) const {
  return sumOverTets(static_cast<int>(set.nodes.size()), [&](int e) {
    const NodeMatrix<Element::kNodes> xe = relativeNodes<Element::kNodes>(x, set.nodes[e]);
    const typename Element::Rest& r = set.rest[e];
    double energy = 0.0;
    for (int q = 0; q < Element::kPoints; ++q)
      energy += r.weight[q] *
                Law::energy(set.law[e], lawPoint(xe * r.grad[q].transpose(), options_).F);
    return energy;
  });
}

template <class Law>
template <class Element>
Eigen::Matrix<double, 3 * Element::kNodes, 3 * Element::kNodes>
HyperelasticModel<Law>::elementStiffness(const LawElements<Element, Law>& set,
                                         const Eigen::VectorXd& x, int e) const {
  constexpr int N = Element::kNodes;
  const NodeMatrix<N> xe = relativeNodes<N>(x, set.nodes[e]);
  const typename Element::Rest& r = set.rest[e];
  Eigen::Matrix<double, 3 * N, 3 * N> Ke = Eigen::Matrix<double, 3 * N, 3 * N>::Zero();
  for (int q = 0; q < Element::kPoints; ++q) {
    LawPoint point = lawPoint(xe * r.grad[q].transpose(), options_);
    subtractPointStiffness<N>(pointTangent<Law>(set.law[e], point, options_), r.grad[q],
                              r.grad[q], r.weight[q], Ke);
  }
  return Ke;
}

template <class Law>
template <class Element>
void HyperelasticModel<Law>::product(const LawElements<Element, Law>& set,
                                     const Eigen::VectorXd& x, const Eigen::VectorXd& d,
                                     double scale, Eigen::VectorXd& out) const {
  constexpr int N = Element::kNodes;
  accumulateElementForces<N>(set.nodes, out, [&](int e, NodeMatrix<N>& fe) {
    const NodeMatrix<N> xe = relativeNodes<N>(x, set.nodes[e]);
    const NodeMatrix<N> de = gatherNodes<N>(d, set.nodes[e]);
    const typename Element::Rest& r = set.rest[e];
    fe.setZero();
    for (int q = 0; q < Element::kPoints; ++q) {
      LawPoint point = lawPoint(xe * r.grad[q].transpose(), options_);
      const Eigen::Matrix3d dF = de * r.grad[q].transpose();
      Eigen::Matrix3d dP;
      if (options_.psdProjection) {
        const Matrix9d A = pointTangent<Law>(set.law[e], point, options_);
        Eigen::Map<Eigen::Matrix<double, 9, 1>>(dP.data()) =
            A * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dF.data());
      } else {
        dP = Law::stressDifferential(set.law[e], point.F, dF);
      }
      fe.noalias() -= (scale * r.weight[q]) * dP * r.grad[q];
    }
    return 0.0;
  });
}

}  // namespace tt
