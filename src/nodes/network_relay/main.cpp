// network_relay: forwards the topic `in` to `out` (remap both; any message type, the relay
// never reads the messages) through a simulated network link, tt::NetworkChannel: delay,
// jitter, loss, outages that drop or hold, reordering, by its private parameters. Placed
// between the simulation and the haptic bridge (launch/degraded_network.launch) it shows what
// a slow, lossy or partitioned network does to the force at the device.
// Publishes its counters on /diagnostics at 1 Hz and logs them when it stops.
#include <ros/ros.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <topic_tools/shape_shifter.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>

#include "periodic_clock.h"
#include "relay_params.h"

namespace tt_nodes {
namespace {

using Message = topic_tools::ShapeShifter;

class NetworkRelay {
 public:
  NetworkRelay(ros::NodeHandle& nh, const RelayParams& params)
      : nh_(nh), channel_(params.profile, params.queue) {
    sub_ = nh_.subscribe("in", 1000, &NetworkRelay::onMessage, this,
                         ros::TransportHints().tcpNoDelay());
    diagnosticsPub_ = nh_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
    diagnosticsTimer_ = nh_.createWallTimer(ros::WallDuration(1.0),
                                            [this](const ros::WallTimerEvent&) { publishDiagnostics(); });
    deliverer_ = std::thread([this] { deliver(); });
  }

  ~NetworkRelay() {
    stop_ = true;
    wake_.notify_all();
    if (deliverer_.joinable()) deliverer_.join();
  }

  std::string summary() {
    std::lock_guard<std::mutex> lock(mutex_);
    const tt::ChannelCounters& c = channel_.counters();
    return "offered " + std::to_string(c.offered) + ", delivered " + std::to_string(c.delivered) +
           ", lost " + std::to_string(c.lost) + ", dropped in outages " +
           std::to_string(c.burstDropped) + ", held in outages " + std::to_string(c.held) +
           ", reordered " + std::to_string(c.reordered) + ", outages " +
           std::to_string(c.outages) + ", queue full " + std::to_string(c.overflow);
  }

 private:
  void onMessage(const ros::MessageEvent<const Message>& event) {
    const Message::ConstPtr& msg = event.getConstMessage();
    std::lock_guard<std::mutex> lock(mutex_);
    if (!pub_) {  // the first message says the type
      pub_ = msg->advertise(nh_, "out", 1000);
      ROS_INFO("network_relay: %s -> %s (%s)", sub_.getTopic().c_str(), pub_.getTopic().c_str(),
               msg->getDataType().c_str());
    }
    const std::uint64_t id = nextId_++;
    if (channel_.offer(id, monotonicSeconds()) != tt::ChannelVerdict::kScheduled) return;
    inFlight_.emplace(id, msg);
    wake_.notify_all();
  }

  // Publishes each message when it is due; sleeps until the next one is.
  void deliver() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
      const double due = channel_.nextDue();
      const double now = monotonicSeconds();
      if (due > now) {
        const double wait = std::min(due - now, 0.1);
        wake_.wait_for(lock, std::chrono::duration<double>(wait));
        continue;
      }
      std::uint64_t id;
      while (channel_.popDue(now, id)) {
        auto it = inFlight_.find(id);
        pub_.publish(*it->second);
        inFlight_.erase(it);
      }
    }
  }

  void publishDiagnostics() {
    diagnostic_msgs::DiagnosticStatus d;
    d.name = "network_relay: " + sub_.getTopic();
    d.hardware_id = "network";
    d.level = diagnostic_msgs::DiagnosticStatus::OK;
    d.message = summary();
    diagnostic_msgs::DiagnosticArray a;
    a.header.stamp = ros::Time::now();
    a.status.push_back(d);
    diagnosticsPub_.publish(a);
  }

  ros::NodeHandle nh_;
  ros::Subscriber sub_;
  ros::Publisher pub_, diagnosticsPub_;
  ros::WallTimer diagnosticsTimer_;

  std::mutex mutex_;  // channel_, inFlight_, pub_
  std::condition_variable wake_;
  tt::NetworkChannel channel_;
  std::unordered_map<std::uint64_t, Message::ConstPtr> inFlight_;
  std::uint64_t nextId_ = 0;
  std::atomic<bool> stop_{false};
  std::thread deliverer_;
};

}  // namespace
}  // namespace tt_nodes

int main(int argc, char** argv) {
  ros::init(argc, argv, "network_relay");
  ros::NodeHandle nh, privateNh("~");
  tt_nodes::RelayParams params;
  const std::vector<std::string> problems = tt_nodes::readRelayParams(privateNh, params);
  for (const std::string& p : problems) ROS_FATAL("network_relay: bad parameter %s", p.c_str());
  if (!problems.empty()) return 2;
  ROS_INFO("network_relay: %s", tt_nodes::describe(params.profile).c_str());
  tt_nodes::NetworkRelay relay(nh, params);
  ros::spin();
  ROS_INFO("network_relay: %s", relay.summary().c_str());
  return 0;
}
