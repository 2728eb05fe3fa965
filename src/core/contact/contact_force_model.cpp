#include "tissue_trainer/core/contact/contact_force_model.h"

#include <algorithm>

namespace tt {
namespace {

Eigen::Vector3d pointOf(const PenaltyContact& c, const Eigen::VectorXd& x) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) p += c.weights[k] * x.segment<3>(3 * c.nodes[k]);
  return p;
}

}  // namespace

double ContactForceModel::depth(const PenaltyContact& c, const Eigen::VectorXd& x) {
  return (pointOf(c, x) - c.toolPoint).dot(c.normal);
}

double ContactForceModel::normalForce(const PenaltyContact& c, const Eigen::VectorXd& x,
                                      const Eigen::VectorXd& v) const {
  const double d = depth(c, x);
  if (!(d > 0.0)) return 0.0;
  double fn = c.stiffness * d;
  if (c.damping > 0.0 && v.size() == x.size()) {
    // Approach speed (positive when tool and tissue move toward each other).
    const double approach = (pointOf(c, v) - toolVelocity).dot(c.normal);
    fn += c.damping * approach;
  }
  return std::max(0.0, fn);
}

double ContactForceModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                                   Eigen::VectorXd& f) const {
  for (const PenaltyContact& c : penalties) {
    const double fn = normalForce(c, x, v);
    if (fn == 0.0) continue;
    for (int k = 0; k < 3; ++k) f.segment<3>(3 * c.nodes[k]) -= c.weights[k] * fn * c.normal;
  }
  for (const GraspSpring& s : springs)
    f.segment<3>(3 * s.node) += s.stiffness * (s.anchor - x.segment<3>(3 * s.node));
  return 0.0;
}

void ContactForceModel::addStiffness(const Eigen::VectorXd& x, double scale,
                                     const SparsePattern& pattern, SparseMatrix& K) const {
  for (const PenaltyContact& c : penalties) {
    if (!(depth(c, x) > 0.0)) continue;
    const Eigen::Matrix3d nn = c.normal * c.normal.transpose();
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        pattern.addNodeBlock(K, c.nodes[a], c.nodes[b],
                             (-scale * c.stiffness * c.weights[a] * c.weights[b]) * nn);
  }
  for (const GraspSpring& s : springs)
    pattern.addNodeBlock(K, s.node, s.node, (-scale * s.stiffness) * Eigen::Matrix3d::Identity());
}

Eigen::Vector3d ContactForceModel::toolForce(const Eigen::VectorXd& x,
                                             const Eigen::VectorXd& v) const {
  Eigen::VectorXd onTissue = Eigen::VectorXd::Zero(x.size());
  addForce(x, v, onTissue);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (Eigen::Index a = 0; a < x.size() / 3; ++a) sum += onTissue.segment<3>(3 * a);
  return -sum;
}

Eigen::Matrix3d ContactForceModel::toolStiffness(const Eigen::VectorXd& x) const {
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
  for (const PenaltyContact& c : penalties)
    if (depth(c, x) > 0.0) K += c.stiffness * c.normal * c.normal.transpose();
  for (const GraspSpring& s : springs) K += s.stiffness * Eigen::Matrix3d::Identity();
  return K;
}

}  // namespace tt
