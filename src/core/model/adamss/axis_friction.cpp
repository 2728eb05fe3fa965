#include "tissue_trainer/core/model/adamss/axis_friction.h"

namespace tt {
namespace adamss {

double AxisFrictionModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                                   Eigen::VectorXd& f) const {
  elements_.addRateForces(x, v, f, [&](const Eigen::Matrix3d& zeta, const Eigen::Matrix3d& rate,
                                       const auto& r) {
    Eigen::Matrix3d g;
    for (int l = 0; l < kAxes; ++l) {
      const Eigen::Vector3d u = zeta.col(l).normalized();
      g.col(l) = -coefficientOf(l, r) * rate.col(l).dot(u) * u;  // Eq. 2.108
    }
    return g;
  });
  return 0.0;
}

void AxisFrictionModel::addVelocityJacobian(const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                            double scale, const SparsePattern& pattern,
                                            SparseMatrix& C) const {
  // dg_l / dzeta_dot_l = -c_l u u^T; the element loops apply -D (x) H (x) D^T, so H = c u u^T.
  elements_.addStiffness(x, scale, pattern, C, [&](const Eigen::Matrix3d& zeta, const auto& r) {
    Matrix9d H = Matrix9d::Zero();
    for (int l = 0; l < kAxes; ++l) {
      const Eigen::Vector3d u = zeta.col(l).normalized();
      H.block<3, 3>(3 * l, 3 * l) = coefficientOf(l, r) * u * u.transpose();
    }
    return H;
  });
}

}  // namespace adamss
}  // namespace tt
