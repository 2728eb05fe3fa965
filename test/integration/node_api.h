#pragma once
// Calls on a running node's XML-RPC slave API, found through the master, for the rostest checks
// that kill nodes or ask them to shut down.
#include <ros/master.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <string>

namespace tt_test {

// Calls `method` on node `node`; false if the node or the call fails.
inline bool callNode(const std::string& node, const std::string& method, XmlRpc::XmlRpcValue call,
                     XmlRpc::XmlRpcValue& reply) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = node;
  if (!ros::master::execute("lookupNode", args, result, payload, false)) return false;
  std::string host;
  std::uint32_t port = 0;
  if (!ros::network::splitURI(static_cast<std::string>(payload), host, port)) return false;
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  return client.execute(method.c_str(), call, reply) && reply.getType() == XmlRpc::XmlRpcValue::TypeArray;
}

// The process id of a running node (getPid); -1 if unknown.
inline int nodePid(const std::string& node) {
  XmlRpc::XmlRpcValue call, reply;
  call[0] = ros::this_node::getName();
  return callNode(node, "getPid", call, reply) && reply.size() >= 3 ? static_cast<int>(reply[2]) : -1;
}

}  // namespace tt_test
