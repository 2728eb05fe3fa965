#include "tissue_trainer/core/kinematics/chain.h"

#include <cmath>
#include <stdexcept>

namespace tt::kin {
namespace {

[[noreturn]] void reject(const std::string& what) { throw std::invalid_argument(what); }

bool finite(const Eigen::Isometry3d& t) { return t.matrix().allFinite(); }

}  // namespace

Chain::Chain(const std::string& rootLink, const std::vector<JointSpec>& joints,
             const std::string& tipLink)
    : rootName_(rootLink) {
  if (rootLink.empty()) reject("kinematic chain: the root link has no name");
  links_.push_back(rootLink);
  parentJoint_.push_back(-1);

  // Variables: movable joints that are not mimics, in the given order.
  for (const JointSpec& j : joints) {
    if (j.type == JointType::kFixed || !j.mimic.empty()) continue;
    if (variableIndex(j.name) >= 0) reject("joint '" + j.name + "': the name appears twice");
    if (std::isnan(j.lower) || std::isnan(j.upper) || j.lower > j.upper)
      reject("joint '" + j.name + "': expected lower limit <= upper limit");
    variables_.push_back({j.name, j.lower, j.upper});
  }

  // Joints in topological order: repeatedly take the joints whose parent link is placed.
  std::vector<bool> placed(joints.size(), false);
  for (size_t done = 0; done < joints.size();) {
    bool progress = false;
    for (size_t k = 0; k < joints.size(); ++k) {
      if (placed[k]) continue;
      const JointSpec& j = joints[k];
      const int parent = linkIndex(j.parent);
      if (parent < 0) continue;
      if (linkIndex(j.child) >= 0)
        reject("joint '" + j.name + "': link '" + j.child + "' already has a parent (or is the root)");
      if (!finite(j.origin)) reject("joint '" + j.name + "': non-finite origin");
      Joint joint{j, parent, static_cast<int>(links_.size()), -1};
      if (j.type != JointType::kFixed) {
        const double norm = j.axis.norm();
        if (!std::isfinite(norm) || norm < 1e-12)
          reject("joint '" + j.name + "': expected a non-zero finite axis");
        joint.spec.axis /= norm;
        if (j.mimic.empty()) {
          joint.spec.multiplier = 1.0;
          joint.spec.offset = 0.0;
          joint.variable = variableIndex(j.name);
        } else {
          joint.variable = variableIndex(j.mimic);
          if (joint.variable < 0)
            reject("joint '" + j.name + "': mimics '" + j.mimic +
                   "', which is not a movable joint of its own");
          if (!std::isfinite(j.multiplier) || !std::isfinite(j.offset))
            reject("joint '" + j.name + "': non-finite mimic multiplier or offset");
        }
      }
      links_.push_back(j.child);
      parentJoint_.push_back(static_cast<int>(joints_.size()));
      joints_.push_back(joint);
      placed[k] = true;
      ++done;
      progress = true;
    }
    if (!progress) {
      for (size_t k = 0; k < joints.size(); ++k)
        if (!placed[k])
          reject("joint '" + joints[k].name + "': parent link '" + joints[k].parent +
                 "' is not connected to the root '" + rootLink + "'");
    }
  }
  tip_ = linkIndex(tipLink);
  if (tip_ < 0) reject("kinematic chain: no link named '" + tipLink + "'");
}

int Chain::variableIndex(const std::string& name) const {
  for (size_t i = 0; i < variables_.size(); ++i)
    if (variables_[i].name == name) return static_cast<int>(i);
  return -1;
}

int Chain::linkIndex(const std::string& name) const {
  for (size_t i = 0; i < links_.size(); ++i)
    if (links_[i] == name) return static_cast<int>(i);
  return -1;
}

double Chain::jointValue(const Joint& joint, const Eigen::VectorXd& q) const {
  if (joint.variable < 0) return 0.0;
  return joint.spec.multiplier * q[joint.variable] + joint.spec.offset;
}

Eigen::Isometry3d Chain::jointTransform(const Joint& joint, const Eigen::VectorXd& q) const {
  const double value = jointValue(joint, q);
  switch (joint.spec.type) {
    case JointType::kRevolute:
      return joint.spec.origin * Eigen::AngleAxisd(value, joint.spec.axis);
    case JointType::kPrismatic:
      return joint.spec.origin * Eigen::Translation3d(value * joint.spec.axis);
    case JointType::kFixed:
      break;
  }
  return joint.spec.origin;
}

void Chain::forward(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>& poses) const {
  if (q.size() != numVariables())
    throw std::invalid_argument("kinematic chain: expected " + std::to_string(numVariables()) +
                                " joint values, got " + std::to_string(q.size()));
  poses.resize(links_.size());
  poses[0].setIdentity();
  for (const Joint& j : joints_) poses[j.childLink] = poses[j.parentLink] * jointTransform(j, q);
}

Eigen::Isometry3d Chain::tipPose(const Eigen::VectorXd& q) const {
  std::vector<Eigen::Isometry3d> poses;
  forward(q, poses);
  return poses[tip_];
}

Jacobian Chain::tipJacobian(const Eigen::VectorXd& q) const {
  std::vector<Eigen::Isometry3d> poses;
  forward(q, poses);
  const Eigen::Vector3d tip = poses[tip_].translation();
  Jacobian jac = Jacobian::Zero(6, numVariables());
  for (int link = tip_; parentJoint_[link] >= 0; link = joints_[parentJoint_[link]].parentLink) {
    const Joint& j = joints_[parentJoint_[link]];
    if (j.variable < 0) continue;
    const Eigen::Isometry3d frame = poses[j.parentLink] * j.spec.origin;
    const Eigen::Vector3d axis = frame.linear() * j.spec.axis;
    const double m = j.spec.multiplier;
    if (j.spec.type == JointType::kRevolute) {
      jac.block<3, 1>(0, j.variable) += m * axis.cross(tip - frame.translation());
      jac.block<3, 1>(3, j.variable) += m * axis;
    } else {
      jac.block<3, 1>(0, j.variable) += m * axis;
    }
  }
  return jac;
}

Eigen::VectorXd Chain::clamp(const Eigen::VectorXd& q) const {
  Eigen::VectorXd out = q;
  for (int i = 0; i < numVariables(); ++i) {
    const Variable& v = variables_[i];
    if (!std::isfinite(out[i])) out[i] = 0.0;
    out[i] = std::min(std::max(out[i], v.lower), v.upper);
  }
  return out;
}

}  // namespace tt::kin
