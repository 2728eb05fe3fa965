#pragma once
// The contact forces on the tissue as a force model of the System, so that implicit
// integrators see their stiffness (an explicit penalty force of a few hundred N/m on nodes of
// a few grams is unstable at a 10 ms step; with its stiffness in the implicit solve it is not).
//
// Penalty contacts, linearised at the contact query: tissue point p(x) = sum_i w_i x_i on a
// surface triangle, outward normal n (tissue -> tool), tool point c = p0 - d0 n. Depth
// d(x) = (p(x) - c) . n, normal force
//     fn = max(0, k d - c_d (v_tool - v_p) . n),
// on the tissue nodes -w_i fn n, on the tool +fn n. Grasp springs: node a held at an anchor
// (moving with the tip), force k_g (anchor - x_a) on the node and the opposite on the tool.
// Stiffness on the tissue: -k w_i w_j n n^T per active penalty, -k_g I per spring (the damping
// part is explicit). Energy is not reported (hasEnergy() false), so the logs' elastic energy
// stays that of the tissue.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "tissue_trainer/core/model/force_model.h"

namespace tt {

struct PenaltyContact {
  std::array<int, 3> nodes{};
  Eigen::Vector3d weights = Eigen::Vector3d::Zero();  // barycentric, sum 1
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, from the tissue toward the tool
  Eigen::Vector3d toolPoint = Eigen::Vector3d::Zero();  // deepest tool point c
  double stiffness = 0.0;                             // N/m
  double damping = 0.0;                               // N s/m
};

struct GraspSpring {
  int node = 0;
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();   // where the tip holds the node (m)
  double stiffness = 0.0;                             // N/m
};

class ContactForceModel : public ForceModel {
 public:
  const char* name() const override { return "contact"; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd&) const override { return 0.0; }
  bool hasEnergy() const override { return false; }
  bool toleratesInversion() const override { return true; }  // no elements
  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;

  // Penetration depth of one penalty contact at x (m; > 0 in contact).
  static double depth(const PenaltyContact& c, const Eigen::VectorXd& x);
  // Normal force of one penalty contact at (x, v) (>= 0, N).
  double normalForce(const PenaltyContact& c, const Eigen::VectorXd& x,
                     const Eigen::VectorXd& v) const;
  // Sum of the forces on the tool (minus the sum of the forces this model puts on the tissue).
  Eigen::Vector3d toolForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v) const;
  // K = -d(tool force)/d(tool position) with the tissue held fixed (N/m).
  Eigen::Matrix3d toolStiffness(const Eigen::VectorXd& x) const;

  std::vector<PenaltyContact> penalties;
  std::vector<GraspSpring> springs;
  Eigen::Vector3d toolVelocity = Eigen::Vector3d::Zero();  // for the damping term (m/s)
};

}  // namespace tt
