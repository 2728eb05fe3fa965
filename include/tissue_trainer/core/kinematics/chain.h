#pragma once
// A kinematic tree of fixed, revolute and prismatic joints as URDF describes them (origin
// transform in the parent link frame, axis in the joint frame, limits, mimic joints), with
// forward kinematics of every link and the spatial Jacobian of one tip link.
//
// The joint variables are the movable joints that are not mimics, in the order the joints
// are given. A mimic joint moves by multiplier * q(source) + offset. Link 0 is the root.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>
#include <string>
#include <vector>

namespace tt::kin {

enum class JointType { kFixed, kRevolute, kPrismatic };

struct JointSpec {
  std::string name;
  std::string parent;  // parent link
  std::string child;   // child link
  JointType type = JointType::kFixed;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // child at q = 0, in parent
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();           // in the joint frame; normalised
  double lower = -std::numeric_limits<double>::infinity();   // rad or m
  double upper = std::numeric_limits<double>::infinity();
  std::string mimic;  // source joint name; empty when the joint is driven on its own
  double multiplier = 1.0;
  double offset = 0.0;
};

struct Variable {
  std::string name;
  double lower, upper;
};

// Linear velocity of the tip origin (rows 0-2) and angular velocity (rows 3-5), root frame.
using Jacobian = Eigen::Matrix<double, 6, Eigen::Dynamic>;

class Chain {
 public:
  Chain() = default;
  // Throws std::invalid_argument (one line naming the joint or link) for an unknown parent,
  // a link with two parents, a loop, a zero or non-finite axis or origin, lower > upper, a
  // mimic of an unknown, fixed or mimic joint, or an unknown tip link.
  Chain(const std::string& rootLink, const std::vector<JointSpec>& joints,
        const std::string& tipLink);

  int numVariables() const { return static_cast<int>(variables_.size()); }
  const std::vector<Variable>& variables() const { return variables_; }
  int variableIndex(const std::string& name) const;  // -1 when unknown

  const std::vector<std::string>& links() const { return links_; }
  int linkIndex(const std::string& name) const;  // -1 when unknown
  int tipLink() const { return tip_; }

  // Joints in topological order (a parent's joint before its children's).
  struct Joint {
    JointSpec spec;
    int parentLink = 0, childLink = 0;
    int variable = -1;  // -1 for fixed joints
  };
  const std::vector<Joint>& joints() const { return joints_; }

  // The joint's own value for the variables q (the mimic rule applied), and its transform
  // parent link -> child link.
  double jointValue(const Joint& joint, const Eigen::VectorXd& q) const;
  Eigen::Isometry3d jointTransform(const Joint& joint, const Eigen::VectorXd& q) const;

  // Pose of every link in the root frame (indexed as links()). q must have numVariables().
  void forward(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>& poses) const;
  Eigen::Isometry3d tipPose(const Eigen::VectorXd& q) const;
  // d(tip twist)/dq: twist = J * qdot, in the root frame, 6 x numVariables().
  Jacobian tipJacobian(const Eigen::VectorXd& q) const;

  // q with every value moved into its limits (non-finite values become the value nearest 0).
  Eigen::VectorXd clamp(const Eigen::VectorXd& q) const;

 private:
  std::string rootName_;
  std::vector<std::string> links_;
  std::vector<Joint> joints_;
  std::vector<int> parentJoint_;  // per link, index into joints_ (-1 for the root)
  std::vector<Variable> variables_;
  int tip_ = 0;
};

}  // namespace tt::kin
