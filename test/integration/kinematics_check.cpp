// With a real master: instrument_kinematics on config/instruments/grasper.urdf against the
// trocar geometry computed by hand (pose, tf, jaw, velocity, bad joint readings), and the
// scripted operator (namespace op) publishing the device at >= 950 Hz.
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TwistStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Bool.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <map>
#include <vector>

#include "stream_rate.h"

namespace {

const Eigen::Vector3d kTrocar(-0.035, 0.075, 0.20);

Eigen::Vector3d shaftDirection(double yaw, double pitch) {
  return {-std::cos(pitch) * std::sin(yaw), -std::sin(pitch), -std::cos(pitch) * std::cos(yaw)};
}

Eigen::Vector3d position(const geometry_msgs::Pose& p) { return {p.position.x, p.position.y, p.position.z}; }
Eigen::Quaterniond orientation(const geometry_msgs::Quaternion& q) { return {q.w, q.x, q.y, q.z}; }

// Spins until pred() holds or the timeout (s) passes.
bool waitFor(const std::function<bool()>& pred, double timeout) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::ok() && ros::WallTime::now() < end) {
    ros::spinOnce();
    if (pred()) return true;
    ros::WallDuration(0.002).sleep();
  }
  return pred();
}

class Kinematics : public ::testing::Test {
 protected:
  void SetUp() override {
    joints_ = nh_.advertise<sensor_msgs::JointState>("/device/measured_js", 10, true);
    poseSub_ = nh_.subscribe("/instrument/measured_cp", 100, &Kinematics::onPose, this);
    twistSub_ = nh_.subscribe("/instrument/measured_cv", 100, &Kinematics::onTwist, this);
    jawSub_ = nh_.subscribe("/instrument/jaw/measured_js", 100, &Kinematics::onJaw, this);
    ASSERT_TRUE(waitFor([&] { return joints_.getNumSubscribers() > 0 && poseSub_.getNumPublishers() > 0; }, 20.0));
  }

  // Publishes the joints and waits for the pose the node computes from them.
  bool send(std::vector<std::string> names, std::vector<double> values, std::vector<double> velocities = {}) {
    sensor_msgs::JointState js;
    js.header.stamp = ros::Time::now() + ros::Duration(1e-3 * ++sent_);
    js.name = std::move(names);
    js.position = std::move(values);
    js.velocity = std::move(velocities);
    const ros::Time stamp = js.header.stamp;
    joints_.publish(js);
    return waitFor([&] { return pose_.header.stamp == stamp && twist_.header.stamp == stamp; }, 5.0);
  }

  void onPose(const geometry_msgs::PoseStamped& m) { pose_ = m; }
  void onTwist(const geometry_msgs::TwistStamped& m) { twist_ = m; }
  void onJaw(const sensor_msgs::JointState& m) { jaw_ = m; }

  ros::NodeHandle nh_;
  ros::Publisher joints_;
  geometry_msgs::PoseStamped pose_;
  geometry_msgs::TwistStamped twist_;
  sensor_msgs::JointState jaw_;
  int sent_ = 0;
  // Last, so they are destroyed first: no callback may run on destroyed members.
  ros::Subscriber poseSub_, twistSub_, jawSub_;
};

// The operator in namespace op: its device topics at >= 950 Hz, each pose on the trocar
// geometry and equal to what instrument_kinematics computes from the joints it published.
TEST(Operator, PublishesTheDeviceAtOneKilohertz) {
  ros::NodeHandle nh;
  std::vector<double> times;
  std::map<double, Eigen::Vector3d> device;
  int offShaft = 0, mismatched = 0, matched = 0;
  bool enabled = false;
  using PoseCallback = boost::function<void(const geometry_msgs::PoseStamped::ConstPtr&)>;
  PoseCallback onDevice = [&](const geometry_msgs::PoseStamped::ConstPtr& msg) {
    const geometry_msgs::PoseStamped& m = *msg;
    times.push_back(ros::WallTime::now().toSec());
    const Eigen::Vector3d p = position(m.pose);
    const Eigen::Vector3d axis = orientation(m.pose.orientation).toRotationMatrix().col(2);
    if (!p.allFinite() || ((p - kTrocar).normalized() - axis).norm() > 1e-6) ++offShaft;
    device[m.header.stamp.toSec()] = p;
  };
  PoseCallback onInstrument = [&](const geometry_msgs::PoseStamped::ConstPtr& msg) {
    const geometry_msgs::PoseStamped& m = *msg;
    const auto it = device.find(m.header.stamp.toSec());
    if (it == device.end()) return;
    ++matched;
    if ((it->second - position(m.pose)).norm() > 1e-9) ++mismatched;
  };
  ros::Subscriber a = nh.subscribe<geometry_msgs::PoseStamped>("/op/device/measured_cp", 2000, onDevice,
                                                                ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  ros::Subscriber b = nh.subscribe<geometry_msgs::PoseStamped>("/op/instrument/measured_cp", 2000, onInstrument);
  boost::function<void(const std_msgs::Bool::ConstPtr&)> onEnable = [&](const std_msgs::Bool::ConstPtr& m) {
    enabled = enabled || m->data;
  };
  ros::Subscriber c = nh.subscribe<std_msgs::Bool>("/op/device/enable", 10, onEnable);
  ASSERT_TRUE(waitFor([&] { return times.size() > 100; }, 30.0));
  times.clear();
  ASSERT_TRUE(waitFor([&] { return !times.empty() && times.back() - times.front() >= 3.0; }, 10.0));
  const double rate = (times.size() - 1) / (times.back() - times.front());
  std::printf("operator /device/measured_cp: %zu messages in %.3f s: %.1f Hz\n", times.size(),
              times.back() - times.front(), rate);
  std::printf("operator: %d device poses matched to /op/instrument/measured_cp by stamp\n", matched);
  EXPECT_GE(tt_test::streamRate(times, 1.0).median, 950.0) << "overall " << rate << " Hz";
  EXPECT_EQ(offShaft, 0);
  EXPECT_GT(matched, 100);  // the kinematics node may drop some under load: not a rate check
  EXPECT_EQ(mismatched, 0);
  EXPECT_TRUE(enabled);
}

// The hand holds the static target of kinematics_hold_task.yaml; a constant force on it
// (/device/servo_cf) moves it by force / stiffness (config/operator.yaml: 400 N/m).
TEST(Operator, ForceOnTheHandDisplacesItByForceOverStiffness) {
  ros::NodeHandle nh;
  Eigen::Vector3d last(NAN, NAN, NAN);
  boost::function<void(const geometry_msgs::PoseStamped::ConstPtr&)> onDevice =
      [&](const geometry_msgs::PoseStamped::ConstPtr& m) { last = position(m->pose); };
  ros::Subscriber sub = nh.subscribe<geometry_msgs::PoseStamped>("/op/device/measured_cp", 100, onDevice);
  ros::Publisher force = nh.advertise<geometry_msgs::WrenchStamped>("/op/device/servo_cf", 10);
  ASSERT_TRUE(waitFor([&] { return force.getNumSubscribers() > 0 && last.allFinite(); }, 20.0));
  const Eigen::Vector3d target(-0.035, 0.075, 0.10);
  EXPECT_LT((last - target).norm(), 2e-6);  // at rest on the target without force
  geometry_msgs::WrenchStamped w;
  w.header.frame_id = "world";
  w.wrench.force.z = 2.0;
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(1.5);
  while (ros::WallTime::now() < end) {  // 200 Hz, faster than the 0.05 s force timeout
    w.header.stamp = ros::Time::now();
    force.publish(w);
    waitFor([] { return false; }, 0.005);
  }
  std::printf("operator hand under 2 N: displaced %.3f mm (force / stiffness: 5.000 mm)\n",
              1e3 * (last.z() - target.z()));
  EXPECT_NEAR(last.z(), target.z() + 2.0 / 400.0, 2e-4);
  EXPECT_NEAR((last.head<2>() - target.head<2>()).norm(), 0.0, 1e-6);
  // Once the force stops (timeout), the hand returns to the target.
  ASSERT_TRUE(waitFor([&] { return (last - target).norm() < 1e-5; }, 3.0));
}

const std::vector<std::string> kNames = {"yaw", "pitch", "roll", "insertion", "jaw"};

TEST_F(Kinematics, PoseAndTfFollowTheTrocarGeometry) {
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  const double yaw = 0.2, pitch = 0.3, roll = 0.4, insertion = 0.12, jaw = 0.5;
  // Repeat the reading (new stamps) until the listener has connected and holds its tf.
  geometry_msgs::TransformStamped tip, upper, lower;
  bool found = false;
  for (int attempt = 0; attempt < 100 && !found; ++attempt) {
    ASSERT_TRUE(send(kNames, {yaw, pitch, roll, insertion, jaw}));
    found = waitFor([&] {
      try {
        tip = buffer.lookupTransform("world", "instrument_tip", pose_.header.stamp);
        upper = buffer.lookupTransform("instrument_tip", "jaw_upper", pose_.header.stamp);
        lower = buffer.lookupTransform("instrument_tip", "jaw_lower", pose_.header.stamp);
        return true;
      } catch (const tf2::TransformException&) {
        return false;
      }
    }, 0.1);
  }
  ASSERT_TRUE(found) << "no tf world -> instrument_tip, jaw_upper, jaw_lower at the reading's stamp";
  const Eigen::Vector3d expected = kTrocar + insertion * shaftDirection(yaw, pitch);
  EXPECT_EQ(pose_.header.frame_id, "world");
  EXPECT_LT((position(pose_.pose) - expected).norm(), 1e-9);
  const Eigen::Matrix3d r = orientation(pose_.pose.orientation).toRotationMatrix();
  EXPECT_LT((r.col(2) - shaftDirection(yaw, pitch)).norm(), 1e-9);
  ASSERT_EQ(jaw_.name.size(), 1u);
  EXPECT_EQ(jaw_.name[0], "jaw");
  EXPECT_DOUBLE_EQ(jaw_.position[0], jaw);

  // tf: world -> instrument_tip through trocar, and the jaws at half the opening each.
  const auto& t = tip.transform.translation;
  EXPECT_LT((Eigen::Vector3d(t.x, t.y, t.z) - expected).norm(), 1e-9);
  EXPECT_LT((orientation(tip.transform.rotation).toRotationMatrix().col(2) - shaftDirection(yaw, pitch)).norm(), 1e-9);
  const Eigen::Vector3d up = orientation(upper.transform.rotation).toRotationMatrix().col(2);
  const Eigen::Vector3d down = orientation(lower.transform.rotation).toRotationMatrix().col(2);
  EXPECT_NEAR(up.y(), std::sin(jaw / 2), 1e-9);
  EXPECT_NEAR(down.y(), -std::sin(jaw / 2), 1e-9);
  const geometry_msgs::TransformStamped trocar = buffer.lookupTransform("world", "trocar", ros::Time(0));
  EXPECT_NEAR(trocar.transform.translation.z, 0.20, 1e-12);
}

TEST_F(Kinematics, VelocityIsTheJacobianTimesTheJointRates) {
  const double yaw = -0.1, pitch = 0.2, insertion = 0.1;
  // Pure insertion rate: the tip slides along the shaft.
  ASSERT_TRUE(send(kNames, {yaw, pitch, 0, insertion, 0}, {0, 0, 0, 0.05, 0}));
  const auto& l = twist_.twist.linear;
  EXPECT_LT((Eigen::Vector3d(l.x, l.y, l.z) - 0.05 * shaftDirection(yaw, pitch)).norm(), 1e-9);
  // Pure yaw rate w about world y through the trocar: v = w y x (tip - trocar).
  ASSERT_TRUE(send(kNames, {yaw, pitch, 0, insertion, 0}, {0.5, 0, 0, 0, 0}));
  const Eigen::Vector3d v = 0.5 * Eigen::Vector3d::UnitY().cross(insertion * shaftDirection(yaw, pitch));
  EXPECT_LT((Eigen::Vector3d(l.x, l.y, l.z) - v).norm(), 1e-9);
  EXPECT_NEAR(twist_.twist.angular.y, 0.5, 1e-9);
}

TEST_F(Kinematics, BadReadingsAreDroppedNotPropagated) {
  ASSERT_TRUE(send(kNames, {0.1, 0.1, 0, 0.1, 0.2}));
  // A non-finite yaw and an unknown name: yaw keeps 0.1, the rest is applied.
  ASSERT_TRUE(send({"yaw", "pitch", "bogus", "insertion"}, {NAN, -0.2, 7.0, 0.15}));
  EXPECT_LT((position(pose_.pose) - (kTrocar + 0.15 * shaftDirection(0.1, -0.2))).norm(), 1e-9);
  EXPECT_TRUE(std::isfinite(twist_.twist.linear.x) && std::isfinite(twist_.twist.angular.z));
  // Names and positions of different lengths: the message is dropped entirely.
  sensor_msgs::JointState bad;
  bad.header.stamp = ros::Time::now();
  bad.name = {"yaw", "pitch"};
  bad.position = {0.5};
  joints_.publish(bad);
  ASSERT_TRUE(send({"insertion"}, {0.2}));
  EXPECT_LT((position(pose_.pose) - (kTrocar + 0.2 * shaftDirection(0.1, -0.2))).norm(), 1e-9);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "kinematics_check");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
