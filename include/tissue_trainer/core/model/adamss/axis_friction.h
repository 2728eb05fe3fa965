#pragma once
// Material friction along the anisotropy axes of the Adamss mass-spring system ("Adamss:
// Advanced Anisotropic Mass-Spring System", Sec. 2.4.2.5): at q_2l the force
// -c_l (zeta_dot_l . zeta_hat_l) zeta_hat_l, the opposite at q_2l+1, which damps the rate of
// change of each axis's length and nothing else (no rigid motion is damped). c_l is
//   bourguignon (Eq. 2.108):        k_d, in N s/m;
//   area (Eqs. 2.109-2.110):        k_d A_l, A_l the rest face area projected on the axis (the
//                                   mean of the axis's two points, as for the springs), k_d in
//                                   Pa s/m;
//   virtual_hexahedron (Eq. 2.111): k_d R_v A_l^0 = k_d V0 / |zeta_l^0| (orthonormal axes).
// Eq. 2.110 uses the current face area; the rest area keeps the force linear in the velocities.
// The force's velocity Jacobian (symmetric, negative semi-definite) lets implicit integrators
// treat it implicitly; its position derivative is left out of the stiffness (addStiffness adds
// nothing), as for the Rayleigh damping of the integrators.
#include "tissue_trainer/core/model/adamss/axis_spring_elements.h"
#include "tissue_trainer/core/model/force_model.h"

namespace tt {
namespace adamss {

enum class AxisFrictionForm { kBourguignon, kArea, kVirtualHexahedron };

class AxisFrictionModel final : public ForceModel {
 public:
  AxisFrictionModel(const Mesh& mesh, double coefficient, AxisFrictionForm form)
      : elements_(mesh), coefficient_(coefficient), form_(form) {}

  const char* name() const override { return "adamss_axis_friction"; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd&) const override { return 0.0; }
  bool hasEnergy() const override { return false; }
  // The position derivative is left out (see above): nothing to add.
  bool hasStiffness() const override { return true; }
  bool hasVelocityJacobian() const override { return true; }
  void addVelocityJacobian(const Eigen::VectorXd& x, const Eigen::VectorXd& v, double scale,
                           const SparsePattern& pattern, SparseMatrix& C) const override;

 private:
  template <int N>
  double coefficientOf(int l, const AxisSpringRest<N>& r) const {
    switch (form_) {
      case AxisFrictionForm::kArea: return coefficient_ * r.area[l];
      case AxisFrictionForm::kVirtualHexahedron: return coefficient_ * r.volume / r.length0[l];
      default: return coefficient_;
    }
  }

  AxisSpringElements elements_;
  double coefficient_;
  AxisFrictionForm form_;
};

}  // namespace adamss
}  // namespace tt
