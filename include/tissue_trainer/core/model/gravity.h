#pragma once
// Constant body force rho g, lumped to the nodes with the system's lumped masses:
// f_i = m_i g, energy -sum_i m_i g . x_i, stiffness zero.
#include <Eigen/Core>

#include "tissue_trainer/core/model/force_model.h"

namespace tt {

class GravityModel : public ForceModel {
 public:
  // mass: lumped mass per DOF (3n, as System::mass); g: acceleration (m/s^2).
  GravityModel(const Eigen::VectorXd& mass, const Eigen::Vector3d& g);

  const char* name() const override { return "gravity"; }
  bool isBodyLoad() const override { return true; }
  bool toleratesInversion() const override { return true; }  // no elements
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;
  // Zero: declared so that implicit integrators accept a system with gravity.
  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd&, double, const SparsePattern&,
                    SparseMatrix&) const override {}

 private:
  Eigen::VectorXd force_;  // m_i g per DOF
};

}  // namespace tt
