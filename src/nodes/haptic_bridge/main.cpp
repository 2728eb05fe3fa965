// haptic_bridge: contact models from the simulation in, device force out at 1 kHz.
#include <ros/ros.h>
#include <ros/xmlrpc_manager.h>

#include <csignal>
#include <exception>

#include "../common/param_reader.h"
#include "bridge_params.h"
#include "haptic_bridge.h"

namespace {

volatile std::sig_atomic_t g_stopRequested = 0;

void requestStop(int) { g_stopRequested = 1; }

// `rosnode kill` and the master ask a node to shut down over XML-RPC; roscpp alone would end
// the node at once with the force still on. Taken like SIGINT: the force fades out first.
void onShutdownRequest(XmlRpc::XmlRpcValue&, XmlRpc::XmlRpcValue& result) {
  g_stopRequested = 1;
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
  ros::XMLRPCManager::instance()->bind("shutdown", onShutdownRequest);
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
