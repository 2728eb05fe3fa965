// haptic_bridge: contact models from the simulation in, device force out at 1 kHz.
#include <ros/ros.h>
#include <ros/xmlrpc_manager.h>

#include <atomic>
#include <csignal>
#include <exception>
#include <string>

#include "../common/param_reader.h"
#include "bridge_params.h"
#include "haptic_bridge.h"

namespace {

std::atomic<bool> g_stopRequested{false};  // lock-free: set from a signal handler and XML-RPC

void requestStop(int) { g_stopRequested = true; }

// `rosnode kill` and the master ask a node to shut down over XML-RPC; roscpp alone would end
// the node at once with the force still on. Taken like SIGINT: the force fades out first.
void onShutdownRequest(XmlRpc::XmlRpcValue& params, XmlRpc::XmlRpcValue& result) {
  std::string reason = "no reason given";
  if (params.getType() == XmlRpc::XmlRpcValue::TypeArray && params.size() > 1 &&
      params[1].getType() == XmlRpc::XmlRpcValue::TypeString)
    reason = static_cast<std::string>(params[1]);
  ROS_WARN("haptic_bridge: shutdown requested (%s): fading the force out", reason.c_str());
  g_stopRequested = true;
  result = ros::xmlrpc::responseInt(1, "", 0);
}

}  // namespace

int main(int argc, char** argv) {
  // SIGINT (roslaunch, Ctrl-C), SIGTERM and a shutdown request stop the node only after the
  // force has faded out.
  ros::init(argc, argv, "haptic_bridge", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, requestStop);
  std::signal(SIGTERM, requestStop);
  ros::NodeHandle nh;  // starts the node, which binds roscpp's own shutdown: replaced here
  ros::XMLRPCManager::instance()->unbind("shutdown");
  if (!ros::XMLRPCManager::instance()->bind("shutdown", onShutdownRequest))
    ROS_WARN("haptic_bridge: could not take the shutdown request over; rosnode kill would end "
             "the node without the fade (SIGINT and SIGTERM still fade)");
  ros::NodeHandle privateNh("~");
  tt_nodes::BridgeParams params;
  try {
    params = tt_nodes::readBridgeParams(privateNh);
  } catch (const tt_nodes::ParamError& e) {
    ROS_FATAL("haptic_bridge: bad parameter %s", e.what());
    return 2;
  }
  tt_nodes::HapticBridge bridge(nh, privateNh, params);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  bridge.start();
  ROS_INFO("haptic_bridge: %.0f Hz, max_force %.2f N, model_timeout %.3f s, device_timeout %.3f s",
           params.rate, params.pipeline.safety.maxForce, params.pipeline.safety.modelTimeout,
           params.deviceTimeout);
  while (!g_stopRequested && ros::ok()) ros::WallDuration(0.002).sleep();
  bridge.stop();
  ROS_INFO("haptic_bridge: force faded out, stopped");
  ros::shutdown();
  return 0;
}
