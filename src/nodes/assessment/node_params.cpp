#include "node_params.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace tt {
namespace {

std::string describe(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string describe(XmlRpc::XmlRpcValue v) {
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeString: return "'" + static_cast<std::string>(v) + "'";
    case XmlRpc::XmlRpcValue::TypeInt: return std::to_string(static_cast<int>(v));
    case XmlRpc::XmlRpcValue::TypeDouble: return describe(static_cast<double>(v));
    case XmlRpc::XmlRpcValue::TypeBoolean: return static_cast<bool>(v) ? "true" : "false";
    case XmlRpc::XmlRpcValue::TypeArray: return "a list";
    case XmlRpc::XmlRpcValue::TypeStruct: return "a map";
    default: return "an unsupported value";
  }
}

[[noreturn]] void fail(const std::string& key, const std::string& expected, const XmlRpc::XmlRpcValue& v) {
  throw std::invalid_argument("parameter ~" + key + ": expected " + expected + ", got " + describe(v));
}

// A number (int or double) if present, else the fallback.
double number(const ros::NodeHandle& nh, const std::string& key, double fallback) {
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(key, v)) return fallback;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble && std::isfinite(static_cast<double>(v)))
    return static_cast<double>(v);
  fail(key, "a finite number", v);
}

}  // namespace

AssessmentNodeParams readAssessmentNodeParams(const ros::NodeHandle& nh) {
  AssessmentNodeParams p;
  AssessmentSettings& s = p.settings;
  s.forceThreshold = number(nh, "force_threshold", s.forceThreshold);
  s.movementSpeedStart = number(nh, "movement_speed_start", s.movementSpeedStart);
  s.movementSpeedStop = number(nh, "movement_speed_stop", s.movementSpeedStop);
  s.resampleRate = number(nh, "resample_rate", s.resampleRate);
  s.smoothingTime = number(nh, "smoothing_time", s.smoothingTime);
  s.maxGap = number(nh, "max_gap", s.maxGap);
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("parameter ~") + e.what());
  }
  p.summaryRate = number(nh, "summary_rate", p.summaryRate);
  if (!(p.summaryRate > 0.0 && p.summaryRate <= 100.0))
    throw std::invalid_argument("parameter ~summary_rate: expected a rate in (0, 100] Hz, got " +
                                describe(p.summaryRate));
  XmlRpc::XmlRpcValue dir;
  if (nh.getParam("output_dir", dir)) {
    if (dir.getType() != XmlRpc::XmlRpcValue::TypeString || static_cast<std::string>(dir).empty())
      fail("output_dir", "a non-empty directory path", dir);
    p.outputDir = static_cast<std::string>(dir);
  }
  return p;
}

}  // namespace tt
