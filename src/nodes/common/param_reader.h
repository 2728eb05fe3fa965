#pragma once
// Node-private parameters, validated: a missing parameter takes its documented default, a
// malformed one throws ParamError with one line naming it and what was expected.
#include <ros/node_handle.h>

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace tt_nodes {

struct ParamError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class ParamReader {
 public:
  explicit ParamReader(const ros::NodeHandle& privateNh) : nh_(privateNh) {}

  double number(const std::string& name, double fallback, double lo, double hi) const {
    const std::string expected = "a number in " + range(lo, hi);
    XmlRpc::XmlRpcValue v;
    double d = fallback;
    if (read(name, expected, v, d) && (d < lo || d > hi)) fail(name, expected, v);
    return d;
  }

  // Any finite number (its range is checked by whoever uses it).
  double number(const std::string& name, double fallback) const {
    XmlRpc::XmlRpcValue v;
    double d = fallback;
    read(name, "a finite number", v, d);
    return d;
  }

  bool flag(const std::string& name, bool fallback) const {
    XmlRpc::XmlRpcValue v;
    if (!nh_.getParam(name, v)) return fallback;
    if (v.getType() != XmlRpc::XmlRpcValue::TypeBoolean) fail(name, "true or false", v);
    return static_cast<bool>(v);
  }

  std::string text(const std::string& name, const std::string& fallback) const {
    XmlRpc::XmlRpcValue v;
    if (!nh_.getParam(name, v)) return fallback;
    if (v.getType() != XmlRpc::XmlRpcValue::TypeString) fail(name, "a string", v);
    return static_cast<std::string>(v);
  }

  // One of `options`; returns its index.
  std::size_t choice(const std::string& name, const std::vector<std::string>& options,
                     std::size_t fallback) const {
    const std::string s = text(name, options.at(fallback));
    for (std::size_t i = 0; i < options.size(); ++i)
      if (s == options[i]) return i;
    std::string expected;
    for (const auto& o : options) expected += (expected.empty() ? "" : " | ") + o;
    throw ParamError(qualified(name) + ": expected one of " + expected + ", got '" + s + "'");
  }

  std::array<double, 3> vector3(const std::string& name, const std::array<double, 3>& fallback) const {
    XmlRpc::XmlRpcValue v;
    if (!nh_.getParam(name, v)) return fallback;
    if (v.getType() != XmlRpc::XmlRpcValue::TypeArray || v.size() != 3) fail(name, "a list of 3 numbers", v);
    std::array<double, 3> out{};
    for (int i = 0; i < 3; ++i) {
      XmlRpc::XmlRpcValue& e = v[i];
      if (e.getType() == XmlRpc::XmlRpcValue::TypeDouble) out[i] = static_cast<double>(e);
      else if (e.getType() == XmlRpc::XmlRpcValue::TypeInt) out[i] = static_cast<int>(e);
      else fail(name, "a list of 3 numbers", v);
      if (!std::isfinite(out[i])) fail(name, "a list of 3 finite numbers", v);
    }
    return out;
  }

  std::string qualified(const std::string& name) const { return nh_.resolveName(name); }

  [[noreturn]] void fail(const std::string& name, const std::string& expected,
                         XmlRpc::XmlRpcValue& got) const {
    std::ostringstream os;
    got.write(os);
    throw ParamError(qualified(name) + ": expected " + expected + ", got " + os.str());
  }

 private:
  // A finite number into d (true), or false when the parameter is not set (d unchanged).
  bool read(const std::string& name, const std::string& expected, XmlRpc::XmlRpcValue& v,
            double& d) const {
    if (!nh_.getParam(name, v)) return false;
    if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) d = static_cast<double>(v);
    else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) d = static_cast<int>(v);
    else fail(name, expected, v);
    if (!std::isfinite(d)) fail(name, expected, v);
    return true;
  }

  static std::string range(double lo, double hi) {
    std::ostringstream os;
    os << "[" << lo << ", " << hi << "]";
    return os.str();
  }

  ros::NodeHandle nh_;
};

}  // namespace tt_nodes
