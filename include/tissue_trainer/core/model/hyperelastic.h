#pragma once
// The generic element force model `hyperelastic`: any material law (material/law.h) on the
// mesh's tets (Tet4, one point) and hexes (Hex8, trilinear, 2x2x2 Gauss points). The energy
// is sum_e sum_q w_q psi(F_q), the physical nodal force of an element f_p = -sum_q w_q P_q g_pq,
// and the stiffness df/dx = -sum_q w_q G_q^T A_q G_q with A_q the law's 9 x 9 tangent
// (projected when asked) and G_q mapping nodal displacements to vec(dF). The law is a
// template argument: its calls are inlined in the element loops, with per-element parameters
// precomputed. Forces and the stiffness-vector product run on tt::threadCount() threads.
#include <Eigen/Core>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "tissue_trainer/core/element/hex8.h"
#include "tissue_trainer/core/element/tet4.h"
#include "tissue_trainer/core/material/law_point.h"
#include "tissue_trainer/core/model/force_model.h"
#include "tissue_trainer/core/model/tet_loops.h"

namespace tt {

// The elements of one kind with their rest data and law parameters, in mesh order.
template <class Element, class Law>
struct LawElements {
  std::vector<typename Element::Nodes> nodes;
  std::vector<typename Element::Rest> rest;
  std::vector<typename Law::Parameters> law;

  // Throws std::invalid_argument naming the element when one is inverted or flat at rest.
  void build(const Mesh& mesh, const std::vector<typename Element::Nodes>& elements,
             const std::vector<Eigen::Matrix3d>& frames, const std::vector<int>& materials,
             const std::vector<typename Law::Constants>& constants, const char* kind) {
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
};

template <class Law>
class HyperelasticModel final : public ForceModel {
 public:
  using Constants = typename Law::Constants;

  // `constants` per material id (Mesh::material, Mesh::hexMaterial).
  HyperelasticModel(const Mesh& mesh, const std::vector<Constants>& constants,
                    const LawOptions& options)
      : options_(options) {
    tets_.build(mesh, mesh.tets, mesh.fibreFrame, mesh.material, constants, "tet");
    hexes_.build(mesh, mesh.hexes, mesh.hexFibreFrame, mesh.hexMaterial, constants, "hex");
  }

  const char* name() const override { return "hyperelastic"; }
  const LawOptions& options() const { return options_; }
  // Inversion handling keeps every element's stress finite and restoring.
  bool toleratesInversion() const override { return options_.inversionThreshold > 0.0; }

  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd&,
                  Eigen::VectorXd& f) const override {
    return forces(tets_, x, f) + forces(hexes_, x, f);
  }

  double energy(const Eigen::VectorXd& x) const override {
    return energyOf(tets_, x) + energyOf(hexes_, x);
  }

  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override {
    addElementStiffness(
        pattern, K, scale, static_cast<int>(tets_.nodes.size()),
        [&](int e) { return elementStiffness(tets_, x, e); }, hexes_.nodes,
        [&](int e) { return elementStiffness(hexes_, x, e); });
  }

  bool hasStiffnessProduct() const override { return true; }
  void addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double scale,
                         Eigen::VectorXd& out) const override {
    product(tets_, x, d, scale, out);
    product(hexes_, x, d, scale, out);
  }

  // Calls edit(parameters) on the law parameters of each listed element (mesh numbering: tets,
  // then hexes), e.g. to set a muscle's activation without rebuilding the model.
  template <class Edit>
  void editParameters(const std::vector<int>& elements, const Edit& edit) {
    const int tets = static_cast<int>(tets_.law.size());
    for (int e : elements) edit(e < tets ? tets_.law.at(e) : hexes_.law.at(e - tets));
  }

 private:
  template <int N>
  static NodeMatrix<N> relativeNodes(const Eigen::VectorXd& x, const std::array<int, N>& nodes) {
    // Positions relative to node 0: the gradients of each point sum to zero, so F is the same
    // and a translated element loses no digits.
    NodeMatrix<N> xe = gatherNodes<N>(x, nodes);
    return xe.colwise() - xe.col(0);
  }

  template <class Element>
  double forces(const LawElements<Element, Law>& set, const Eigen::VectorXd& x,
                Eigen::VectorXd& f) const {
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

  template <class Element>
  double energyOf(const LawElements<Element, Law>& set, const Eigen::VectorXd& x) const {
    return sumOverTets(static_cast<int>(set.nodes.size()), [&](int e) {
      const NodeMatrix<Element::kNodes> xe = relativeNodes<Element::kNodes>(x, set.nodes[e]);
      const typename Element::Rest& r = set.rest[e];
      double energy = 0.0;
      for (int q = 0; q < Element::kPoints; ++q)
        energy += r.weight[q] * Law::energy(set.law[e], lawPoint(xe * r.grad[q].transpose(),
                                                                   options_).F);
      return energy;
    });
  }

  // df/dx of element e (3N x 3N, node-major: row 3p + i).
  template <class Element>
  Eigen::Matrix<double, 3 * Element::kNodes, 3 * Element::kNodes> elementStiffness(
      const LawElements<Element, Law>& set, const Eigen::VectorXd& x, int e) const {
    constexpr int N = Element::kNodes;
    const NodeMatrix<N> xe = relativeNodes<N>(x, set.nodes[e]);
    const typename Element::Rest& r = set.rest[e];
    Eigen::Matrix<double, 3 * N, 3 * N> Ke = Eigen::Matrix<double, 3 * N, 3 * N>::Zero();
    for (int q = 0; q < Element::kPoints; ++q) {
      LawPoint point = lawPoint(xe * r.grad[q].transpose(), options_);
      const Matrix9d A = pointTangent<Law>(set.law[e], point, options_);
      // G(i + 3 j, 3 p + i) = g_pj: vec(dF) = G vec(dx).
      Eigen::Matrix<double, 9, 3 * N> G = Eigen::Matrix<double, 9, 3 * N>::Zero();
      for (int p = 0; p < N; ++p)
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i) G(i + 3 * j, 3 * p + i) = r.grad[q](j, p);
      Ke.noalias() -= r.weight[q] * (G.transpose() * A * G);
    }
    return Ke;
  }

  template <class Element>
  void product(const LawElements<Element, Law>& set, const Eigen::VectorXd& x,
               const Eigen::VectorXd& d, double scale, Eigen::VectorXd& out) const {
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

  LawOptions options_;
  LawElements<Tet4, Law> tets_;
  LawElements<Hex8, Law> hexes_;
};

}  // namespace tt
