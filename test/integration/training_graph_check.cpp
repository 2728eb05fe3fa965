// Watches the running training graph (training_graph.test): the haptic bridge's wrench
// stream, the simulation's contact models and status, and the renderer's images, over a
// window that starts with the first wrench.
#include <geometry_msgs/WrenchStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <tissue_trainer/ContactModel.h>
#include <tissue_trainer/TissueStatus.h>

#include "stream_rate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

struct Wrench {
  double t;
  double fx, fy, fz;
  double norm() const { return std::sqrt(fx * fx + fy * fy + fz * fz); }
};

struct Recording {
  std::vector<Wrench> wrenches;
  int contactModels = 0, inContact = 0, nonFiniteContacts = 0;
  double peakContactForce = 0.0;
  int statuses = 0, unstable = 0, behind = 0;
  int images = 0, goodImages = 0;
};

bool finite3(double a, double b, double c) {
  return std::isfinite(a) && std::isfinite(b) && std::isfinite(c);
}

Recording record(double window) {
  ros::NodeHandle node;
  Recording rec;
  rec.wrenches.reserve(static_cast<std::size_t>(window * 1200));
  bool started = false;
  auto onWrench = [&](const geometry_msgs::WrenchStamped::ConstPtr& msg) {
    const auto& m = *msg;
    started = true;
    rec.wrenches.push_back({m.header.stamp.toSec(), m.wrench.force.x, m.wrench.force.y,
                            m.wrench.force.z});
  };
  auto onContact = [&](const tissue_trainer::ContactModel::ConstPtr& msg) {
    const auto& m = *msg;
    if (!started) return;
    ++rec.contactModels;
    if (!finite3(m.force.x, m.force.y, m.force.z)) ++rec.nonFiniteContacts;
    if (!m.in_contact) return;
    ++rec.inContact;
    rec.peakContactForce = std::max(rec.peakContactForce, std::hypot(m.force.x, m.force.y, m.force.z));
  };
  auto onStatus = [&](const tissue_trainer::TissueStatus::ConstPtr& msg) {
    const auto& m = *msg;
    if (!started) return;
    ++rec.statuses;
    rec.unstable += !m.stable;
    rec.behind += m.behind_schedule;
  };
  auto onImage = [&](const sensor_msgs::Image::ConstPtr& msg) {
    const auto& m = *msg;
    if (!started) return;
    ++rec.images;
    rec.goodImages += m.width == 640 && m.height == 480 && m.encoding == "rgb8" &&
                      m.data.size() == 640u * 480u * 3u;
  };
  ros::Subscriber s1 = node.subscribe<geometry_msgs::WrenchStamped>(
      "/device/servo_cf", 5000, onWrench, ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  ros::Subscriber s2 = node.subscribe<tissue_trainer::ContactModel>("/tissue/contact", 1000, onContact);
  ros::Subscriber s3 = node.subscribe<tissue_trainer::TissueStatus>("/tissue/status", 1000, onStatus);
  ros::Subscriber s4 = node.subscribe<sensor_msgs::Image>("/camera/image_raw", 10, onImage);

  const ros::WallTime giveUp = ros::WallTime::now() + ros::WallDuration(60.0);
  while (ros::ok() && !started && ros::WallTime::now() < giveUp) {
    ros::spinOnce();
    ros::WallDuration(0.001).sleep();
  }
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(window);
  while (ros::ok() && ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.0005).sleep();
  }
  return rec;
}

constexpr double kStampJitter = 50e-6;  // s

double param(const std::string& name) {
  double value = NAN;
  if (!ros::param::get(name, value)) ADD_FAILURE() << "parameter " << name << " is not set";
  return value;
}

TEST(TrainingGraph, HapticStreamIsFastFiniteBoundedAndContinuousWithContactAndImages) {
  ros::NodeHandle priv("~");
  const double window = priv.param("window", 12.0);
  const double maxForce = param("/haptic_bridge/max_force");
  const double maxForceRate = param("/haptic_bridge/max_force_rate");
  const double simRate = param("/simulation/rate");
  const Recording rec = record(window);

  ASSERT_GT(rec.wrenches.size(), 100u) << "no wrench stream on /device/servo_cf";
  std::vector<double> stamps;
  for (const Wrench& w : rec.wrenches) stamps.push_back(w.t);
  const tt_test::StreamRate rates = tt_test::streamRate(stamps, 2.0);
  const double rate = rates.median;
  EXPECT_GE(rates.median, 950.0) << "bridge rate, median of " << rates.windows << " 2 s windows";
  // A gap longer than the device's own force timeout (config/operator.yaml) would let the
  // device drop the force on its own.
  EXPECT_LT(rates.largestGap, param("/operator/force_timeout")) << "longest gap between wrenches";

  int nonFinite = 0, overForce = 0, overRate = 0;
  double peak = 0.0, largestStep = 0.0;
  for (std::size_t i = 0; i < rec.wrenches.size(); ++i) {
    const Wrench& w = rec.wrenches[i];
    if (!finite3(w.fx, w.fy, w.fz)) { ++nonFinite; continue; }
    peak = std::max(peak, w.norm());
    overForce += w.norm() > maxForce * (1.0 + 1e-9);
    if (i == 0) continue;
    const Wrench& p = rec.wrenches[i - 1];
    const double step = std::hypot(w.fx - p.fx, w.fy - p.fy, w.fz - p.fz);
    const double dt = w.t - p.t;
    largestStep = std::max(largestStep, step);
    // The bridge limits the change per tick to max_force_rate times its own tick length. The
    // stamps carry that tick's time shifted by a ROS-clock offset that the publisher re-reads
    // with up to 25 us of error each time (haptic_bridge.cpp, RosStamper), so two stamps can
    // be up to 50 us closer than the ticks were.
    overRate += step > maxForceRate * (dt + kStampJitter) * (1.0 + 1e-6) + 1e-9;
  }
  EXPECT_EQ(nonFinite, 0);
  EXPECT_EQ(overForce, 0) << "peak " << peak << " N, limit " << maxForce;
  EXPECT_EQ(overRate, 0) << "largest step between samples " << largestStep << " N";

  EXPECT_GT(rec.inContact, 0) << "the scripted operator never touched the tissue";
  EXPECT_EQ(rec.nonFiniteContacts, 0);
  EXPECT_GE(rec.peakContactForce, 0.05);
  EXPECT_LE(rec.peakContactForce, 20.0);
  EXPECT_GT(peak, 0.02) << "contact happened but no force reached the device";

  EXPECT_GE(rec.statuses, 0.9 * simRate * window) << "simulation did not keep its rate";
  EXPECT_EQ(rec.unstable, 0);
  EXPECT_GT(rec.goodImages, 0) << rec.images << " images, none 640x480 rgb8";

  RecordProperty("bridge_rate_hz", std::to_string(rate));
  RecordProperty("peak_device_force_n", std::to_string(peak));
  RecordProperty("peak_contact_force_n", std::to_string(rec.peakContactForce));
  RecordProperty("status_messages", rec.statuses);
  RecordProperty("behind_schedule_steps", rec.behind);
  RecordProperty("images", rec.images);
  std::printf("bridge %.1f Hz (median of %d windows, slowest %.1f Hz, longest gap %.1f ms), peak device force %.3f N, peak contact force %.3f N, %d status "
              "(%d behind), %d images in %.1f s\n",
              rate, rates.windows, rates.lowest, 1e3 * rates.largestGap, peak, rec.peakContactForce, rec.statuses, rec.behind, rec.images, window);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "training_graph_check");
  ros::NodeHandle node;
  return RUN_ALL_TESTS();
}
