#pragma once
// The haptic bridge's parameters (config/haptic_bridge.yaml), read and validated.
#include <ros/node_handle.h>

#include "tissue_trainer/core/haptics/haptic_pipeline.h"

namespace tt_nodes {

struct BridgeParams {
  double rate = 1000.0;          // Hz, loop and /device/servo_cf rate
  bool requireEnable = false;    // gate the force on /device/enable
  double deviceTimeout = 0.05;   // s: an older device pose counts as unsafe (force fades out)
  tt::HapticPipelineOptions pipeline;
};

// Throws ParamError (one line naming the parameter) for a malformed or inconsistent value.
BridgeParams readBridgeParams(const ros::NodeHandle& privateNh);

}  // namespace tt_nodes
