#include "bridge_params.h"

#include <limits>

#include "../common/param_reader.h"

namespace tt_nodes {

BridgeParams readBridgeParams(const ros::NodeHandle& privateNh) {
  const ParamReader p(privateNh);
  const double inf = std::numeric_limits<double>::infinity();
  BridgeParams b;
  b.rate = p.number("rate", 1000.0, 100.0, 10000.0);
  b.requireEnable = p.flag("require_enable", false);
  b.deviceTimeout = p.number("device_timeout", 0.05, 1e-4, 10.0);

  tt::SafetyOptions& s = b.pipeline.safety;
  s.maxForce = p.number("max_force", 5.0, 1e-6, 100.0);
  s.maxForceRate = p.number("max_force_rate", 1000.0, 1e-6, 1e6);
  s.modelTimeout = p.number("model_timeout", 0.1, 1e-4, 10.0);
  s.fadeTime = p.number("fade_time", 0.03, 1e-4, 0.05);
  s.resumeTime = p.number("resume_time", 0.1, 1e-4, 10.0);
  s.nominalPeriod = 1.0 / b.rate;
  if (s.maxForceRate * s.fadeTime < s.maxForce)
    throw ParamError(p.qualified("max_force_rate") + ": expected max_force_rate * fade_time >= " +
                     "max_force (the fade must reach zero within fade_time under the rate limit)");

  tt::ExtrapolatorOptions& e = b.pipeline.extrapolation;
  e.blendTime = p.number("blend_time", 0.015, 0.0, 1.0);
  e.blendShape = p.choice("blend_shape", {"smoothstep", "linear"}, 0) == 0
                     ? tt::BlendShape::kSmoothstep : tt::BlendShape::kLinear;
  e.blendMethod = p.choice("blend_method", {"offset", "fields"}, 0) == 0
                      ? tt::BlendMethod::kOffset : tt::BlendMethod::kFields;
  e.mode = p.choice("extrapolation", {"linear", "zero_order_hold"}, 0) == 0
               ? tt::ExtrapolationMode::kLinear : tt::ExtrapolationMode::kZeroOrderHold;
  e.maxStiffness = p.number("max_stiffness", 1e4, 1e-6, inf);

  b.pipeline.statsWindow = static_cast<std::size_t>(2.0 * b.rate);  // 2 s of ticks
  b.pipeline.overrunThreshold = 1.5 / b.rate;
  return b;
}

}  // namespace tt_nodes
