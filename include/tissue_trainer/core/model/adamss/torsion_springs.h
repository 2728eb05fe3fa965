#pragma once
// The torsion springs of the Adamss mass-spring system ("Adamss: Advanced Anisotropic
// Mass-Spring System", Sec. 2.4.2.1): between each pair of an element's axes (l, m) a spring on
// the angle alpha_lm between them (Eq. 2.32), theta = alpha_lm - alpha_lm^0, or on its cosine,
// theta = zeta_hat_l . zeta_hat_m - (the same at rest); with psi = sum_i k_lm,i theta^i
// (linear, Eqs. 2.40-2.45; cubic, Eqs. 2.47-2.50).
//
// Two forms:
//   printed (Eqs. 2.40-2.55): f_2l = -psi zeta_hat_m, f_2m = -psi zeta_hat_l, the opposite at
//     q_2l+1 and q_2m+1; k in N. Its area form multiplies the forces on axis l's points by the
//     rest face area A_l projected on the axis (the mean of its two points', so the forces stay
//     equal and opposite), k in Pa. The direction zeta_hat_m is the cheap stand-in the text
//     chooses for the direction in which the angle changes: the forces are not the gradient of
//     an energy, and their moment about the element is -psi (|zeta_l| - |zeta_m|) zeta_hat_l x
//     zeta_hat_m, zero only for axes of equal length. There is no energy (hasEnergy is false).
//   gradient: the forces of the energy E = s sum_i k_lm,i theta^(i+1) / (i + 1), with s = 1 (k
//     in J) or, in the area form, s = V0 (k in Pa: an energy density, like a shear modulus).
//     No net force or moment.
// The gradient form has its analytic stiffness (the Hessian of E in the axes, carried to the
// nodes by Eq. 2.29), so implicit integrators accept it; the printed form has none: explicit
// integrators, or implicit ones with finite-difference Jacobians.
#include <array>

#include "tissue_trainer/core/model/adamss/axis_spring_elements.h"
#include "tissue_trainer/core/model/force_model.h"

namespace tt {
namespace adamss {

struct TorsionSpringParameters {
  static constexpr int kMaxOrder = 3;
  static constexpr int kPairs = 3;
  static constexpr int pair[kPairs][2] = {{0, 1}, {0, 2}, {1, 2}};
  // k[pair][i - 1]: the coefficient of order i for the pairs (fibre, sheet), (fibre,
  // sheet-normal), (sheet, sheet-normal).
  std::array<std::array<double, kMaxOrder>, kPairs> k{};
  bool cosine = false;    // the measure: the cosine of the angle, or the angle
  bool gradient = false;  // the form: the energy gradient, or the printed forces
  bool areaForm = false;
};

class TorsionSpringModel final : public ForceModel {
 public:
  TorsionSpringModel(const Mesh& mesh, const TorsionSpringParameters& parameters);

  const char* name() const override { return "adamss_torsion_springs"; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;
  bool hasEnergy() const override { return parameters_.gradient; }
  bool hasStiffness() const override { return parameters_.gradient; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;
  bool hasStiffnessProduct() const override { return parameters_.gradient; }
  void addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double scale,
                         Eigen::VectorXd& out) const override;

 private:
  AxisSpringElements elements_;
  TorsionSpringParameters parameters_;
};

}  // namespace adamss
}  // namespace tt
