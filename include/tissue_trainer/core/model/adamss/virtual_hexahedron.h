#pragma once
// The method of the virtual hexahedron ("Adamss: Advanced Anisotropic Mass-Spring System",
// Sec. 2.4.2): the forces of any material law (material/law.h) applied at the intersection
// points of each element's anisotropy axes (model/adamss/axes.h) and carried to the nodes by
// the coefficient matrix C (Eq. 2.29).
//
// Form and sign. Eq. 2.56, with the global deformation gradient F and P = F B S B^T (B the
// element's frame, S the law's stress in it), puts R_v A_l P n_l at the point q_2l and the
// opposite at q_2l+1, where n_l is the unit outward normal of the virtual hexahedron's face
// through q_2l, A_l that face's area (Eq. 2.57) and R_v = V0 / V_h (Eq. 2.58). Distributed by
// Eq. 2.29 this is P h_p at node p, with the constant lever h_p = R_v sum_l A_l n_l D_pl and
// D_pl = C_p,2l - C_p,2l+1. That is the gradient of the element's energy, not the restoring
// force, so the model returns -P h_p: the sign of the springs (Eq. 2.35) and of v' = M^-1 F
// (Eq. 2.126).
//
// Tets: the shape functions are affine, so D_pl = g_p . zeta_l^0 (g_p = grad N_p), and the face
// normals of a parallelepiped scaled by their areas are V_h times the reciprocal basis of its
// edges zeta_l^0, so h_p = V0 g_p: the virtual hexahedron is the one-point finite element of
// the same law, exactly, for any non-degenerate axes. Hexes: F is taken at the centre (Eqs.
// 2.63-2.67 at xi = 0); h_p = V0 g_p(0) when the axes run along the edges of a rectangular
// hex, and only there is the force the gradient of the energy V0 W(F(0)) this model reports
// (nonConservativeHexes() counts the others; their stiffness is the exact derivative of the
// force and is not symmetric). Hex modes that leave F(0) unchanged (hourglass modes, Sec.
// 2.9.1) have no force.
//
// Axis approximation (Eqs. 2.59-2.62): F in the axes' frame from the stretches of the three
// axes and the angles between them, and the point forces of Eq. 2.74 corrected,
// f_2l = -R_v A_l sum_k S_kl zeta_k / |zeta_k^0| with the current axes zeta_k, f_2l+1 = -f_2l.
// It is exact for stretches along the axes and for symmetric shears with equal axis stretches,
// and approximate otherwise, also when one axis stays orthogonal to the others (a 30 % simple
// shear is off by about 1e-2 in C = F^T F). It needs orthonormal rest axes, has no stiffness
// (explicit integrators, or implicit ones with finite-difference Jacobians), and its energy
// V0 W(F) is not the potential of its force.
//
// Distribution (Sec. 2.4.2.3). `axes` carries the point forces to the nodes by C (Eq. 2.29).
// `vertices` uses instead the equal-share matrix the thesis names for an isotropic volume
// preservation: each point's force in equal parts to the nodes of the face holding it
// (1/3 on a tet's face, 1/4 on a hex's), so the lever is h'_p = R_v sum_l A_l n_l D'_pl with
// D' from that matrix. The net force stays zero (every column of the matrix sums to 1 and the
// two point forces of an axis are opposite), but the force is the gradient of no energy
// (hasEnergy() is false, energy() 0) and its moment about the element is not zero in general:
// moving a point force to its face's centroid moves its line of action. Where every point is
// its face's centroid (a rectangular hex with the axes along its edges) the two are the same.
//
// The model's members are defined in virtual_hexahedron_impl.h and compiled once per registered
// law, in its registration file (model/law_model_factory.h); other files link them.
#include <Eigen/Core>
#include <Eigen/LU>
#include <stdexcept>
#include <string>
#include <vector>

#include "tissue_trainer/core/element/hex8.h"
#include "tissue_trainer/core/element/tet4.h"
#include "tissue_trainer/core/material/law_point.h"
#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/model/adamss/axes.h"
#include "tissue_trainer/core/model/adamss/virtual_hexahedron_options.h"
#include "tissue_trainer/core/model/force_model.h"
#include "tissue_trainer/core/model/tet_loops.h"

namespace tt {
namespace adamss {

// What one element's virtual hexahedron needs, computed once.
template <int N>
struct VirtualHexahedronRest {
  NodeMatrix<N> gradient = NodeMatrix<N>::Zero();  // grad_X N_p at the centre (column p)
  NodeMatrix<N> lever = NodeMatrix<N>::Zero();     // h_p: the force at node p is -P h_p
  Eigen::Matrix<double, N, kAxes> axisWeights =    // D: the current axes are x_e D (Eq. 2.5)
      Eigen::Matrix<double, N, kAxes>::Zero();
  // D (axes) or D' (vertices): a point force pair f_2l = -f_2l+1 reaches the nodes as f_2l D^T.
  Eigen::Matrix<double, N, kAxes> distributionWeights = Eigen::Matrix<double, N, kAxes>::Zero();
  Eigen::Vector3d pointArea = Eigen::Vector3d::Zero();  // R_v A_l
  Eigen::Vector3d length0 = Eigen::Vector3d::Zero();    // |zeta_l^0|
  Eigen::Matrix3d axes0 = Eigen::Matrix3d::Identity();  // unit rest axes (columns)
  double volume = 0.0;                                  // V0
};

// The rest data of tet `nodes` or hex `nodes` of `mesh` with its axes. Returns false when the
// element is flat or inverted at rest or its axes span no volume.
bool tetVirtualHexahedron(const Mesh& mesh, const Tet& nodes, const AxisRest<Tet4>& axes,
                          PointForceDistribution distribution,
                          VirtualHexahedronRest<Tet4::kNodes>& out);
bool hexVirtualHexahedron(const Mesh& mesh, const Hex& nodes, const AxisRest<Hex8>& axes,
                          PointForceDistribution distribution,
                          VirtualHexahedronRest<Hex8::kNodes>& out);

// True when the lever is the gradient's, h_p = V0 g_p (relative 1e-9): the force is then the
// gradient of the element's energy.
template <int N>
bool isConservative(const VirtualHexahedronRest<N>& r) {
  return (r.lever - r.volume * r.gradient).norm() <= 1e-9 * r.volume * r.gradient.norm();
}

// F in the axes' frame from the current axes (columns) and their rest lengths (Eqs. 2.59-2.62):
// F = diag(lambda) (I + Gamma), beta_ij = (pi/2 - alpha_ij) / 2 with alpha_ij the angle between
// axes i and j, lambda_i = |zeta_i| / |zeta_i^0| prod_(j != i) cos beta_ij, gamma_ij =
// tan beta_ij. For axes orthogonal at rest.
Eigen::Matrix3d axisDeformationGradient(const Eigen::Matrix3d& zeta,
                                        const Eigen::Vector3d& length0);

template <class Element, class Law>
struct VirtualHexahedra {
  std::vector<typename Element::Nodes> nodes;
  std::vector<VirtualHexahedronRest<Element::kNodes>> rest;
  std::vector<typename Law::Parameters> law;
};

template <class Law>
class VirtualHexahedronModel final : public ForceModel {
 public:
  using Constants = typename Law::Constants;

  // `constants` per material id. Throws std::invalid_argument naming the element ("tet 3")
  // whose axes or rest shape the method cannot use.
  VirtualHexahedronModel(const Mesh& mesh, const std::vector<Constants>& constants,
                         const LawOptions& options, DeformationGradientSource source,
                         PointForceDistribution distribution = PointForceDistribution::kAxes);

  const char* name() const override { return "virtual_hexahedron"; }
  DeformationGradientSource source() const { return source_; }
  PointForceDistribution distribution() const { return distribution_; }
  // Hexes whose force is not the gradient of their energy (axes not along the edges of a
  // rectangular hex, or the `vertices` distribution).
  int nonConservativeHexes() const { return nonConservativeHexes_; }
  // Tets whose force is not the gradient of their energy (only with `vertices`).
  int nonConservativeTets() const { return nonConservativeTets_; }
  // With `vertices` the model has an energy only where the distribution is that of `axes`.
  bool hasEnergy() const override {
    return distribution_ == PointForceDistribution::kAxes ||
           (nonConservativeTets_ == 0 && nonConservativeHexes_ == 0);
  }
  bool toleratesInversion() const override { return options_.inversionThreshold > 0.0; }

  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;

  bool hasStiffness() const override { return shapeFunctions(); }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;

  bool hasStiffnessProduct() const override { return shapeFunctions(); }
  void addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double scale,
                         Eigen::VectorXd& out) const override;

 private:
  bool shapeFunctions() const { return source_ == DeformationGradientSource::kShapeFunctions; }

  template <class Element, class RestOf>
  void build(const Mesh& mesh, const std::vector<typename Element::Nodes>& elements,
             const std::vector<AxisRest<Element>>& axes, const std::vector<int>& materials,
             const std::vector<Constants>& constants, const char* kind,
             VirtualHexahedra<Element, Law>& set, RestOf restOf);
  template <int N>
  static NodeMatrix<N> relativeNodes(const Eigen::VectorXd& x, const std::array<int, N>& nodes);
  // The point where the law is evaluated: F(centre), or the axis approximation's F.
  template <int N>
  LawPoint pointOf(const NodeMatrix<N>& xe, const VirtualHexahedronRest<N>& r) const;
  template <class Element>
  double forces(const VirtualHexahedra<Element, Law>& set, const Eigen::VectorXd& x,
                Eigen::VectorXd& f) const;
  template <class Element>
  double energyOf(const VirtualHexahedra<Element, Law>& set, const Eigen::VectorXd& x) const;
  // df/dx of element e (3N x 3N, node-major): df_p = -dP[dF] h_p with dF = dx_e G^T.
  template <class Element>
  Eigen::Matrix<double, 3 * Element::kNodes, 3 * Element::kNodes> elementStiffness(
      const VirtualHexahedra<Element, Law>& set, const Eigen::VectorXd& x, int e) const;
  template <class Element>
  void product(const VirtualHexahedra<Element, Law>& set, const Eigen::VectorXd& x,
               const Eigen::VectorXd& d, double scale, Eigen::VectorXd& out) const;

  LawOptions options_;
  DeformationGradientSource source_;
  PointForceDistribution distribution_;
  VirtualHexahedra<Tet4, Law> tets_;
  VirtualHexahedra<Hex8, Law> hexes_;
  int nonConservativeHexes_ = 0;
  int nonConservativeTets_ = 0;
};

}  // namespace adamss
}  // namespace tt
