#include "tissue_trainer/core/model/gravity.h"

namespace tt {

GravityModel::GravityModel(const Eigen::VectorXd& mass, const Eigen::Vector3d& g)
    : force_(mass.size()) {
  for (Eigen::Index i = 0; i < mass.size(); ++i) force_[i] = mass[i] * g[i % 3];
}

double GravityModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& /*v*/,
                              Eigen::VectorXd& f) const {
  f += force_;
  return energy(x);
}

double GravityModel::energy(const Eigen::VectorXd& x) const { return -force_.dot(x); }

}  // namespace tt
