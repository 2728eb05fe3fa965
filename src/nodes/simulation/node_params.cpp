#include "node_params.h"

#include <ros/console.h>

#include <cmath>

namespace tt_nodes {
namespace {

bool fail(const ros::NodeHandle& nh, const std::string& name, const std::string& expected) {
  ROS_FATAL("parameter %s: expected %s", nh.resolveName(name).c_str(), expected.c_str());
  return false;
}

}  // namespace

bool readNumber(const ros::NodeHandle& nh, const std::string& name, double& value, double min,
                bool exclusiveMin) {
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(name, v)) return true;
  double x;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) x = static_cast<double>(v);
  else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) x = static_cast<int>(v);
  else return fail(nh, name, "a number");
  const std::string range = (exclusiveMin ? "a finite number > " : "a finite number >= ") + std::to_string(min);
  if (!std::isfinite(x) || (exclusiveMin ? !(x > min) : !(x >= min))) return fail(nh, name, range);
  value = x;
  return true;
}

bool readInteger(const ros::NodeHandle& nh, const std::string& name, int& value, int min) {
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(name, v)) return true;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeInt || static_cast<int>(v) < min)
    return fail(nh, name, "an integer >= " + std::to_string(min));
  value = static_cast<int>(v);
  return true;
}

bool readString(const ros::NodeHandle& nh, const std::string& name, std::string& value,
                bool required) {
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(name, v)) return required ? fail(nh, name, "a string (it is required)") : true;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeString || static_cast<std::string>(v).empty())
    return fail(nh, name, "a non-empty string");
  value = static_cast<std::string>(v);
  return true;
}

}  // namespace tt_nodes
