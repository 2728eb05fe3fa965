#pragma once
// Active forces of the Adamss mass-spring system ("Adamss: Advanced Anisotropic Mass-Spring
// System", Sec. 2.4.3): a tension t(time) generated inside every volume element (a muscle's
// contraction), following a time curve read at each step's start (beginStep). A positive t
// contracts: the forces pull the element's faces (isotropic) or the two intersection points of
// its fibre axis (anisotropic) towards each other. The forces are internal: on every element
// their resultant and their moment are zero.
//
// Anisotropic (Eqs. 2.115-2.116, the virtual hexahedron form): along the fibre axis zeta_0,
// with u = zeta_0 / |zeta_0|, the point q_0 gets -c u and q_1 gets +c u, carried to the nodes
// by the coefficient matrix C (Eq. 2.29), with
//   mode tension:  c = t R_v A^t,  A^t = (zeta_1 x zeta_2) . u the current area of the virtual
//                  hexahedron's fibre face projected on the fibre, R_v = V0 / V_h^0 (Eq. 2.58);
//                  so c = t V0 |det Z| / (|det Z^0| |zeta_0|), Z the current axes as columns;
//   mode force:    c = t R_v A^0 = t V0 / |zeta_0^0| (the rest area, fixed magnitude).
// Eqs. 2.115-2.116 put half of this at each point and use the unprojected area |zeta_1 x zeta_2|.
// With the full c at each point, as the virtual hexahedron's Eq. 2.56 gives for the stress
// t e_0 (x) e_0, the forces on a linear tet are those of the finite element with the active
// Cauchy stress t u (x) u (tension) or the active first Piola-Kirchhoff stress t u (x) N
// (force, N the rest fibre): t is a stress, in Pa. The projection makes the force that of the
// stress across the face when shear tilts the face against the fibre; the two areas agree
// while the fibre stays normal to it.
//
// Isotropic (Eq. 2.112, with the face area it lacks): every face j, of vector area S_j n_j
// (n_j outward), gets the force -t S_j n_j, shared among its nodes p by the weights
// integral over the face of N_p dA. On a triangle, and on a parallelogram quad, these are the
// equal shares 1/n of Eq. 2.112; on a warped or trapezoidal hex face the equal shares would
// leave a net moment, and the integral weights do not. Summed over the faces this is
//   mode tension:  f_p = -t dV/dx_p, V the element's current volume (an isotropic active Cauchy
//                  stress t I; energy t V);
//   mode force:    f_p = -t (V0/V)^(2/3) dV/dx_p: the rest areas scaled by the element's mean
//                  area change (energy 3 t V0^(2/3) V^(1/3)). Scaling each face by its own
//                  S_j^0 / S_j^t, as the text suggests, would leave a net force on the element.
//
// Stiffness: all four variants give df/dx (the force model has it for implicit integrators).
// Energy: at a fixed tension three variants have the potentials above (potential(x)); the
// anisotropic tension variant has none (its stiffness is not symmetric). The model reports no
// energy to the system all the same: the tension changes with time, so the potential changes
// without work, and the stability guard's energy balance must count the active forces' work
// instead (as it does for a model without energy).
#include <memory>

#include "tissue_trainer/core/model/adamss/axis_spring_elements.h"
#include "tissue_trainer/core/model/force_model.h"
#include "tissue_trainer/core/model/time_curve.h"

namespace tt {
namespace adamss {

enum class ActiveForm { kAnisotropic, kIsotropic };
enum class ActiveMode { kTension, kForce };

class ActiveTensionModel final : public ForceModel {
 public:
  // Throws std::invalid_argument naming an element whose axes cannot be built (anisotropic)
  // or whose rest volume is not positive.
  ActiveTensionModel(const Mesh& mesh, ActiveForm form, ActiveMode mode, TimeCurve curve);

  const char* name() const override { return "adamss_active_tension"; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd&) const override { return 0.0; }
  bool hasEnergy() const override { return false; }
  // The potential of the force at the current tension (0 for the anisotropic tension
  // variant, which has none).
  double potential(const Eigen::VectorXd& x) const;
  bool hasPotential() const { return !anisotropicTension(); }
  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;
  bool hasStiffnessProduct() const override { return true; }
  void addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double scale,
                         Eigen::VectorXd& out) const override;

  bool needsStepUpdates() const override { return true; }
  void beginStep(double t, const Eigen::VectorXd&, const Eigen::VectorXd&) override {
    tension_ = curve_.value(t);
  }
  ActiveForm form() const { return form_; }
  ActiveMode mode() const { return mode_; }
  // The tension in use: the curve's value at the last beginStep (at t = 0 before the first).
  double tension() const { return tension_; }

 private:
  bool anisotropicTension() const {
    return form_ == ActiveForm::kAnisotropic && mode_ == ActiveMode::kTension;
  }
  // Anisotropic: the point force g_0 at q_0 (columns 1, 2 zero) and -dg/dzeta.
  template <int N>
  Eigen::Matrix3d fibreForce(const Eigen::Matrix3d& zeta, const AxisSpringRest<N>& r) const;
  template <int N>
  Matrix9d fibreForceJacobian(const Eigen::Matrix3d& zeta, const AxisSpringRest<N>& r) const;

  template <int N>
  void addVolumeForces(const std::vector<std::array<int, N>>& elements,
                         const std::vector<double>& restVolume, const Eigen::VectorXd& x,
                         Eigen::VectorXd& f) const;
  template <int N>
  Eigen::Matrix<double, 3 * N, 3 * N> volumeStiffness(const NodeMatrix<N>& xe, double V0) const;
  template <int N>
  void addVolumeStiffnessTimes(const std::vector<std::array<int, N>>& elements,
                               const std::vector<double>& restVolume, const Eigen::VectorXd& x,
                               const Eigen::VectorXd& d, double scale, Eigen::VectorXd& out) const;
  // The isotropic potential's factor on V and its first two derivatives: E = t phi(V).
  void volumePotential(double V, double V0, double& phi, double& dphi, double& ddphi) const;

  ActiveForm form_;
  ActiveMode mode_;
  TimeCurve curve_;
  double tension_ = 0.0;
  std::unique_ptr<AxisSpringElements> axes_;  // anisotropic
  std::vector<Tet> tets_;                     // isotropic
  std::vector<double> tetVolume0_;
  std::vector<Hex> hexes_;
  std::vector<double> hexVolume0_;
};

}  // namespace adamss
}  // namespace tt
