#pragma once
// The network relay's private parameters (~delay_ms, ~loss, ...), validated: every bad one
// gives its own error line.
#include <ros/node_handle.h>

#include <cstddef>
#include <string>
#include <vector>

#include "tissue_trainer/core/haptics/network_channel.h"

namespace tt_nodes {

struct RelayParams {
  tt::NetworkProfile profile;
  std::size_t queue = 4096;  // messages in flight at most
};

// Reads the parameters into `params`; returns one line per bad parameter (empty: all good).
std::vector<std::string> readRelayParams(const ros::NodeHandle& privateNh, RelayParams& params);

// "delay 20 ms, jitter 5 ms, loss 10 %, ..." for the start-up log line.
std::string describe(const tt::NetworkProfile& p);

}  // namespace tt_nodes
