#pragma once
// The axial springs of the Adamss mass-spring system ("Adamss: Advanced Anisotropic
// Mass-Spring System", Sec. 2.4.2.1): along each of an element's three axes a polynomial spring
// between the axis's two intersection points, f_2l = -phi_l zeta_hat_l at q_2l and the opposite
// at q_2l+1 (Eqs. 2.33-2.34), with
//   length form (Eqs. 2.35-2.36):  phi_l = sum_i k_l,i (|zeta_l| - |zeta_l^0|)^i, k in N/m^i;
//   area form (Eqs. 2.37-2.39):    phi_l = A_l sum_i k_l,i eps^i, eps = |zeta_l| / |zeta_l^0| - 1,
//                                  k in Pa, A_l the rest face area projected on the axis.
// Two readings differ from the print. Eqs. 2.37-2.39 multiply a stiffness in Pa by an area and
// a length difference, which is not a force: the argument is read as the strain eps. And the
// print computes the two points' forces with their own faces' areas, which puts a net force on
// the element (the faces of a tet that a ray enters and leaves through have different projected
// areas); here A_l is the mean of the two, so both points get equal and opposite forces.
// Both forms are the gradient of an energy of |zeta_l|, which gives the stiffness.
#include <array>

#include "tissue_trainer/core/model/adamss/axis_spring_elements.h"
#include "tissue_trainer/core/model/force_model.h"

namespace tt {
namespace adamss {

struct AxialSpringParameters {
  static constexpr int kMaxOrder = 3;
  // k[l][i - 1]: the coefficient of order i on axis l (fibre, sheet, sheet-normal).
  std::array<std::array<double, kMaxOrder>, kAxes> k{};
  bool areaForm = false;
};

class AxialSpringModel final : public ForceModel {
 public:
  AxialSpringModel(const Mesh& mesh, const AxialSpringParameters& parameters)
      : elements_(mesh), parameters_(parameters) {}

  const char* name() const override { return "adamss_axial_springs"; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;
  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;
  bool hasStiffnessProduct() const override { return true; }
  void addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double scale,
                         Eigen::VectorXd& out) const override;

 private:
  AxisSpringElements elements_;
  AxialSpringParameters parameters_;
};

}  // namespace adamss
}  // namespace tt
