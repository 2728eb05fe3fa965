// With a real master: the scripted operator holds the task until the simulation's first
// status (operator_wait.test). In namespace waits the check publishes that status 4 s after
// the operator's device stream starts: enable must stay false until then and turn true
// start_delay (0.5 s) after it. In namespace alone no status ever comes: the operator starts
// after its wait_for_simulation (3 s) plus start_delay.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Bool.h>

#include <functional>
#include <mutex>
#include <string>

#include "tissue_trainer/TissueStatus.h"

namespace {

// When a namespace's operator started publishing the device, and when enable first turned true
// (wall s; 0: not yet).
struct StartWatch {
  std::mutex m;
  double firstDevice = 0.0, firstEnable = 0.0;

  void device() {
    std::lock_guard<std::mutex> l(m);
    if (firstDevice == 0.0) firstDevice = ros::WallTime::now().toSec();
  }
  void enable(const std_msgs::Bool& b) {
    std::lock_guard<std::mutex> l(m);
    if (b.data && firstEnable == 0.0) firstEnable = ros::WallTime::now().toSec();
  }
  std::pair<double, double> read() {
    std::lock_guard<std::mutex> l(m);
    return {firstDevice, firstEnable};
  }
};

bool waitFor(const std::function<bool()>& done, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    if (done()) return true;
    ros::WallDuration(0.01).sleep();
  }
  return done();
}

TEST(OperatorWait, TheTaskStartsAfterTheSimulationsFirstStatus) {
  ros::NodeHandle nh;
  StartWatch waits, alone;
  ros::Subscriber a = nh.subscribe<sensor_msgs::JointState>(
      "/waits/device/measured_js", 10, [&](const sensor_msgs::JointState::ConstPtr&) { waits.device(); });
  ros::Subscriber b = nh.subscribe<std_msgs::Bool>(
      "/waits/device/enable", 10, [&](const std_msgs::Bool::ConstPtr& m) { waits.enable(*m); });
  ros::Subscriber c = nh.subscribe<sensor_msgs::JointState>(
      "/alone/device/measured_js", 10, [&](const sensor_msgs::JointState::ConstPtr&) { alone.device(); });
  ros::Subscriber d = nh.subscribe<std_msgs::Bool>(
      "/alone/device/enable", 10, [&](const std_msgs::Bool::ConstPtr& m) { alone.enable(*m); });
  ros::Publisher status = nh.advertise<tissue_trainer::TissueStatus>("/waits/tissue/status", 1);
  ros::AsyncSpinner spinner(2);
  spinner.start();

  ASSERT_TRUE(waitFor([&] { return waits.read().first > 0.0 && status.getNumSubscribers() > 0; }, 30.0))
      << "the waiting operator never published the device or never subscribed to the status";
  ros::WallDuration(4.0).sleep();
  EXPECT_EQ(waits.read().second, 0.0) << "the task started without a simulation status";
  const double statusSent = ros::WallTime::now().toSec();
  status.publish(tissue_trainer::TissueStatus());
  ASSERT_TRUE(waitFor([&] { return waits.read().second > 0.0; }, 5.0)) << "no start after the status";
  const double afterStatus = waits.read().second - statusSent;
  RecordProperty("start_after_status_s", std::to_string(afterStatus));
  EXPECT_GT(afterStatus, 0.5 - 0.05);  // start_delay, within the 100 Hz enable stream
  EXPECT_LT(afterStatus, 0.5 + 0.5);

  ASSERT_TRUE(waitFor([&] { return alone.read().second > 0.0; }, 20.0)) << "the operator without a simulation never started";
  const auto [device, enabled] = alone.read();
  const double afterDevice = enabled - device;
  RecordProperty("start_without_simulation_s", std::to_string(afterDevice));
  // wait_for_simulation + start_delay, less the time the check took to connect to the
  // operator's device stream (0.27 s seen on a loaded machine).
  EXPECT_GT(afterDevice, 3.0 + 0.5 - 0.5);
  EXPECT_LT(afterDevice, 3.0 + 0.5 + 1.0);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "operator_wait_check");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
