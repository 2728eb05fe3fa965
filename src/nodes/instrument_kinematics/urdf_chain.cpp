#include "urdf_chain.h"

#include <urdf/model.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <sstream>

namespace tt::nodes {
namespace {

kin::JointSpec convert(const urdf::Joint& j) {
  kin::JointSpec s;
  s.name = j.name;
  s.parent = j.parent_link_name;
  s.child = j.child_link_name;
  const urdf::Pose& o = j.parent_to_joint_origin_transform;
  s.origin = Eigen::Translation3d(o.position.x, o.position.y, o.position.z) *
             Eigen::Quaterniond(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z);
  s.axis = Eigen::Vector3d(j.axis.x, j.axis.y, j.axis.z);
  switch (j.type) {
    case urdf::Joint::FIXED: s.type = kin::JointType::kFixed; break;
    case urdf::Joint::CONTINUOUS: s.type = kin::JointType::kRevolute; break;
    case urdf::Joint::REVOLUTE: s.type = kin::JointType::kRevolute; break;
    case urdf::Joint::PRISMATIC: s.type = kin::JointType::kPrismatic; break;
    default:
      throw std::runtime_error("URDF joint '" + j.name +
                               "': expected a fixed, revolute, continuous or prismatic joint");
  }
  if (j.limits && (j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::PRISMATIC)) {
    s.lower = j.limits->lower;
    s.upper = j.limits->upper;
  }
  if (j.mimic) {
    s.mimic = j.mimic->joint_name;
    s.multiplier = j.mimic->multiplier;
    s.offset = j.mimic->offset;
  }
  return s;
}

[[noreturn]] void badParam(const std::string& name, const std::string& expected,
                           XmlRpc::XmlRpcValue& value) {
  std::ostringstream text;
  value.write(text);
  throw std::runtime_error("~" + name + ": expected " + expected + ", got '" + text.str() + "'");
}

std::string shortNumber(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

}  // namespace

kin::Chain chainFromUrdf(const std::string& xml, const std::string& tipLink) {
  urdf::Model model;
  if (!model.initString(xml)) throw std::runtime_error("robot description: not a valid URDF");
  const urdf::LinkConstSharedPtr root = model.getRoot();
  if (!root) throw std::runtime_error("robot description: the URDF has no root link");
  std::vector<kin::JointSpec> joints;
  // Depth-first from the root, so parents come before children.
  std::function<void(const urdf::Link&)> walk = [&](const urdf::Link& link) {
    for (const auto& j : link.child_joints) joints.push_back(convert(*j));
    for (const auto& child : link.child_links) walk(*child);
  };
  walk(*root);
  try {
    return kin::Chain(root->name, joints, tipLink);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("robot description: ") + e.what());
  }
}

kin::Chain chainFromParameter(const ros::NodeHandle& nh, const std::string& param,
                              const std::string& tipLink) {
  std::string xml;
  if (!nh.getParam(param, xml))
    throw std::runtime_error(param + ": expected the instrument URDF (a string parameter), "
                             "e.g. config/instruments/grasper.urdf");
  return chainFromUrdf(xml, tipLink);
}

std::string stringParam(const ros::NodeHandle& pn, const std::string& name, const std::string& fallback) {
  XmlRpc::XmlRpcValue v;
  if (!pn.getParam(name, v)) return fallback;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeString || static_cast<std::string&>(v).empty())
    badParam(name, "a non-empty string", v);
  return static_cast<std::string&>(v);
}

std::string requiredStringParam(const ros::NodeHandle& pn, const std::string& name) {
  if (!pn.hasParam(name)) throw std::runtime_error("~" + name + ": missing required parameter");
  return stringParam(pn, name, "");
}

double numberParam(const ros::NodeHandle& pn, const std::string& name, double fallback,
                   double minimum, double maximum) {
  XmlRpc::XmlRpcValue v;
  if (!pn.getParam(name, v)) return fallback;
  double x;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
    x = static_cast<double>(v);
  else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
    x = static_cast<int>(v);
  else
    badParam(name, "a number", v);
  if (!std::isfinite(x) || x < minimum || x > maximum)
    badParam(name, "a number in [" + shortNumber(minimum) + ", " + shortNumber(maximum) + "]", v);
  return x;
}

bool boolParam(const ros::NodeHandle& pn, const std::string& name, bool fallback) {
  XmlRpc::XmlRpcValue v;
  if (!pn.getParam(name, v)) return fallback;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeBoolean) badParam(name, "true or false", v);
  return static_cast<bool>(v);
}

}  // namespace tt::nodes
