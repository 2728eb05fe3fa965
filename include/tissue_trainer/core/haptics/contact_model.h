#pragma once
// The contact model the simulation publishes for the haptic loop (Jeffrey, "A non-linear
// anisotropic Finite Element Method for surgical simulation", Sec. 3, after Picinbono 2002):
// the force f0 on the tool at tool-tip position x0 and the contact stiffness
// K = -df/dx there, so that near x0 the force is the linear field
//     f(x) = f0 - K (x - x0).
// Sign check: a spring pulling the tool back to its rest point r, f(x) = -k (x - r), has
// K = k I; for passive tissue K is positive semidefinite and pushing in raises the reaction.
#include <cstdint>

#include <Eigen/Core>

namespace tt {

struct ContactModel {
  double stamp = 0.0;          // header stamp (s), on the simulation host's clock
  std::uint64_t sequence = 0;  // grows by at least one per published model
  bool inContact = false;      // false: the force is zero, whatever f0 and K hold
  Eigen::Vector3d x0 = Eigen::Vector3d::Zero();  // tool-tip position (m) the model is taken at
  Eigen::Vector3d f0 = Eigen::Vector3d::Zero();  // force on the tool at x0 (N)
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero();   // contact stiffness -df/dx at x0 (N/m)
  double simTime = 0.0;        // simulation time the model belongs to (s)

  // Every number (times, x0, f0, K) is finite.
  bool isFinite() const;
};

// The linear force field f(x) = f0 - K (x - x0) (K = -df/dx), the form every model and every
// blend of two models takes.
struct LinearForceField {
  Eigen::Vector3d x0 = Eigen::Vector3d::Zero();
  Eigen::Vector3d f0 = Eigen::Vector3d::Zero();
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero();

  Eigen::Vector3d at(const Eigen::Vector3d& x) const { return f0 - K * (x - x0); }

  // (1 - w) a + w b as one field, anchored at b.x0 (the same force for every x).
  static LinearForceField blend(const LinearForceField& a, const LinearForceField& b, double w);
};

}  // namespace tt
