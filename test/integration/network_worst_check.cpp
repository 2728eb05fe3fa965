// Watches the haptic bridge behind the worst network profile (network_worst.test) over the
// scripted palpation, from the moment the operator enables the device: every wrench finite,
// within max_force, every change within max_force_rate; the relay degraded the stream enough
// to trip the watchdog, and force still reached the device.
#include <geometry_msgs/WrenchStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <tissue_trainer/ContactModel.h>
#include <tissue_trainer/HapticStatus.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

constexpr double kStampAllowance = 0.0002;  // s: the filter limits by its own tick length

struct Wrench {
  double t;
  std::uint32_t seq;
  double fx, fy, fz;
  double norm() const { return std::sqrt(fx * fx + fy * fy + fz * fz); }
};

double param(const std::string& name) {
  double value = NAN;
  if (!ros::param::get(name, value)) ADD_FAILURE() << "parameter " << name << " is not set";
  return value;
}

TEST(NetworkWorst, BridgeKeepsItsForceAndRateLimits) {
  ros::NodeHandle node, priv("~");
  const double window = priv.param("window", 8.0);
  const double maxForce = param("/haptic_bridge/max_force");
  const double maxForceRate = param("/haptic_bridge/max_force_rate");
  std::vector<Wrench> wrenches;
  wrenches.reserve(static_cast<std::size_t>(window * 1200));
  bool enabled = false;
  int relayed = 0;
  tissue_trainer::HapticStatus last;
  auto onWrench = [&](const geometry_msgs::WrenchStamped::ConstPtr& m) {
    if (!enabled) return;
    wrenches.push_back({m->header.stamp.toSec(), m->header.seq, m->wrench.force.x,
                        m->wrench.force.y, m->wrench.force.z});
  };
  ros::Subscriber s1 = node.subscribe<geometry_msgs::WrenchStamped>(
      "/device/servo_cf", 5000, onWrench, ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  ros::Subscriber s2 = node.subscribe<std_msgs::Bool>(
      "/device/enable", 10, [&](const std_msgs::Bool::ConstPtr& m) { enabled = enabled || m->data; });
  ros::Subscriber s3 = node.subscribe<tissue_trainer::ContactModel>(
      "/tissue/contact_relayed", 1000, [&](const tissue_trainer::ContactModel::ConstPtr&) { ++relayed; });
  ros::Subscriber s4 = node.subscribe<tissue_trainer::HapticStatus>(
      "/haptic_bridge/status", 100, [&](const tissue_trainer::HapticStatus::ConstPtr& m) { last = *m; });

  const ros::WallTime giveUp = ros::WallTime::now() + ros::WallDuration(60.0);
  while (ros::ok() && !enabled && ros::WallTime::now() < giveUp) {
    ros::spinOnce();
    ros::WallDuration(0.001).sleep();
  }
  ASSERT_TRUE(enabled) << "the operator never enabled the device";
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(window);
  while (ros::ok() && ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.0005).sleep();
  }

  ASSERT_GT(wrenches.size(), 1000u) << "no wrench stream on /device/servo_cf";
  int nonFinite = 0, overForce = 0, overRate = 0;
  double peak = 0.0, largestStep = 0.0;
  for (std::size_t i = 0; i < wrenches.size(); ++i) {
    const Wrench& w = wrenches[i];
    if (!std::isfinite(w.fx) || !std::isfinite(w.fy) || !std::isfinite(w.fz)) {
      ++nonFinite;
      continue;
    }
    peak = std::max(peak, w.norm());
    overForce += w.norm() > maxForce * (1.0 + 1e-9);
    if (i == 0) continue;
    const Wrench& p = wrenches[i - 1];
    const double step = std::hypot(w.fx - p.fx, w.fy - p.fy, w.fz - p.fz);
    largestStep = std::max(largestStep, step);
    overRate += step > maxForceRate * (w.t - p.t + kStampAllowance) + 1e-9;
  }
  EXPECT_EQ(nonFinite, 0);
  EXPECT_EQ(overForce, 0) << "peak " << peak << " N, limit " << maxForce << " N";
  EXPECT_EQ(overRate, 0) << "largest step " << largestStep << " N, limit " << maxForceRate << " N/s";
  // Not vacuous: the network was bad enough to trip the watchdog, and force still came through.
  EXPECT_GT(relayed, 0) << "no contact model came through the relay";
  EXPECT_GE(last.watchdog_trips, 1u) << "the worst profile never tripped the watchdog";
  EXPECT_GT(peak, 0.2) << "no force reached the device during the palpation";
  std::printf("[network_worst] %zu wrenches, peak %.3f N, largest step %.4f N, %d models relayed, "
              "%lu watchdog trips, %lu rate-limited ticks\n",
              wrenches.size(), peak, largestStep, relayed,
              static_cast<unsigned long>(last.watchdog_trips), static_cast<unsigned long>(last.rate_limited));
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "network_worst_check");
  ros::NodeHandle node;
  return RUN_ALL_TESTS();
}
