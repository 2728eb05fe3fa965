#pragma once
// The generic element force model `hyperelastic`: any material law (material/law.h) on the
// mesh's tets (Tet4, one point) and hexes (Hex8, trilinear, 2x2x2 Gauss points). The energy
// is sum_e sum_q w_q psi(F_q), the physical nodal force of an element f_p = -sum_q w_q P_q g_pq,
// and the stiffness df/dx = -sum_q w_q G_q^T A_q G_q with A_q the law's 9 x 9 tangent
// (projected when asked) and G_q mapping nodal displacements to vec(dF). The law is a
// template argument: its calls are inlined in the element loops, with per-element parameters
// precomputed. Forces and the stiffness-vector product run on tt::threadCount() threads.
// The members are defined in hyperelastic_impl.h and compiled once per registered law, in its
// registration file (model/law_model_factory.h); other files include this header and link them.
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
             const std::vector<typename Law::Constants>& constants, const char* kind);
};

template <class Law>
class HyperelasticModel final : public ForceModel {
 public:
  using Constants = typename Law::Constants;

  // `constants` per material id (Mesh::material, Mesh::hexMaterial).
  HyperelasticModel(const Mesh& mesh, const std::vector<Constants>& constants,
                    const LawOptions& options);

  const char* name() const override { return "hyperelastic"; }
  const LawOptions& options() const { return options_; }
  // Inversion handling keeps every element's stress finite and restoring.
  bool toleratesInversion() const override { return options_.inversionThreshold > 0.0; }

  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;

  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;

  bool hasStiffnessProduct() const override { return true; }
  void addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double scale,
                         Eigen::VectorXd& out) const override;

  // Calls edit(parameters) on the law parameters of each listed element (mesh numbering: tets,
  // then hexes), e.g. to set a muscle's activation without rebuilding the model.
  template <class Edit>
  void editParameters(const std::vector<int>& elements, const Edit& edit) {
    const int tets = static_cast<int>(tets_.law.size());
    for (int e : elements) edit(e < tets ? tets_.law.at(e) : hexes_.law.at(e - tets));
  }

 private:
  template <int N>
  static NodeMatrix<N> relativeNodes(const Eigen::VectorXd& x, const std::array<int, N>& nodes);
  template <class Element>
  double forces(const LawElements<Element, Law>& set, const Eigen::VectorXd& x,
                Eigen::VectorXd& f) const;
  template <class Element>
  double energyOf(const LawElements<Element, Law>& set, const Eigen::VectorXd& x) const;
  // df/dx of element e (3N x 3N, node-major: row 3p + i).
  template <class Element>
  Eigen::Matrix<double, 3 * Element::kNodes, 3 * Element::kNodes> elementStiffness(
      const LawElements<Element, Law>& set, const Eigen::VectorXd& x, int e) const;
  template <class Element>
  void product(const LawElements<Element, Law>& set, const Eigen::VectorXd& x,
               const Eigen::VectorXd& d, double scale, Eigen::VectorXd& out) const;

  LawOptions options_;
  LawElements<Tet4, Law> tets_;
  LawElements<Hex8, Law> hexes_;
};

}  // namespace tt
