// instrument_kinematics: device joint readings -> instrument pose, velocity, jaw and tf.
// The URDF (~description_param, default /robot_description) becomes a core kinematic chain;
// each /device/measured_js message updates the named joints (unknown names, non-finite values
// and missing joints are dropped and counted, with a throttled warning), then the node
// broadcasts tf for every movable joint (fixed joints once, as static transforms) and
// publishes /instrument/measured_cp, /instrument/measured_cv and /instrument/jaw/measured_js.
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/TwistStamped.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include <cmath>

#include "eigen_msgs.h"
#include "urdf_chain.h"

namespace tt::nodes {
namespace {

geometry_msgs::TransformStamped stampedTransform(const Eigen::Isometry3d& t, const std::string& parent,
                                             const std::string& child, const ros::Time& stamp) {
  geometry_msgs::TransformStamped msg;
  msg.transform = transformMsg(t);
  msg.header.stamp = stamp;
  msg.header.frame_id = parent;
  msg.child_frame_id = child;
  return msg;
}

class InstrumentKinematics {
 public:
  InstrumentKinematics(ros::NodeHandle& nh, ros::NodeHandle& pn)
      : chain_(chainFromParameter(nh, stringParam(pn, "description_param", "/robot_description"),
                                  stringParam(pn, "tip_link", "instrument_tip"))),
        publishTf_(boolParam(pn, "publish_tf", true)),
        q_(chain_.clamp(Eigen::VectorXd::Zero(chain_.numVariables()))),
        qd_(Eigen::VectorXd::Zero(chain_.numVariables())),
        seen_(chain_.numVariables(), false) {
    jaw_ = chain_.variableIndex("jaw");
    world_ = chain_.links()[0];
    pose_ = nh.advertise<geometry_msgs::PoseStamped>("instrument/measured_cp", 10);
    twist_ = nh.advertise<geometry_msgs::TwistStamped>("instrument/measured_cv", 10);
    jawPub_ = nh.advertise<sensor_msgs::JointState>("instrument/jaw/measured_js", 10);
    if (publishTf_) broadcastFixedJoints();
    sub_ = nh.subscribe("device/measured_js", 10, &InstrumentKinematics::onJoints, this,
                        ros::TransportHints().tcpNoDelay());
    ROS_INFO("instrument_kinematics: %d joint variables, %zu links, tip '%s'",
             chain_.numVariables(), chain_.links().size(), chain_.links()[chain_.tipLink()].c_str());
  }

 private:
  void broadcastFixedJoints() {
    std::vector<geometry_msgs::TransformStamped> fixed;
    for (const auto& j : chain_.joints())
      if (j.variable < 0)
        fixed.push_back(stampedTransform(j.spec.origin, chain_.links()[j.parentLink],
                                     chain_.links()[j.childLink], ros::Time::now()));
    staticTf_.sendTransform(fixed);
  }

  // Updates q_ (and qd_) from the message; returns false when nothing usable arrived.
  bool update(const sensor_msgs::JointState& msg, const ros::Time& stamp) {
    if (msg.position.size() != msg.name.size()) {
      ++malformed_;
      return false;
    }
    const bool velocities = msg.velocity.size() == msg.name.size();
    const Eigen::VectorXd previous = q_;
    std::fill(seen_.begin(), seen_.end(), false);
    Eigen::VectorXd given = Eigen::VectorXd::Constant(chain_.numVariables(), NAN);
    int used = 0;
    for (size_t i = 0; i < msg.name.size(); ++i) {
      const int v = chain_.variableIndex(msg.name[i]);
      if (v < 0) {
        ++unknown_;
        continue;
      }
      if (!std::isfinite(msg.position[i])) {
        ++nonFinite_;
        continue;
      }
      q_[v] = msg.position[i];
      seen_[v] = true;
      ++used;
      if (velocities && std::isfinite(msg.velocity[i])) given[v] = msg.velocity[i];
    }
    for (bool s : seen_) missing_ += s ? 0 : 1;
    if (used == 0) return false;
    // Velocity: as reported, else the difference quotient since the previous message.
    const double dt = haveStamp_ ? (stamp - lastStamp_).toSec() : 0.0;
    for (int v = 0; v < chain_.numVariables(); ++v) {
      if (std::isfinite(given[v]))
        qd_[v] = given[v];
      else if (!seen_[v])
        qd_[v] = 0.0;
      else
        qd_[v] = dt > 0.0 ? (q_[v] - previous[v]) / dt : 0.0;
    }
    lastStamp_ = stamp;
    haveStamp_ = true;
    return true;
  }

  void onJoints(const sensor_msgs::JointState& msg) {
    const ros::Time stamp = msg.header.stamp.isZero() ? ros::Time::now() : msg.header.stamp;
    const bool ok = update(msg, stamp);
    if (malformed_ + unknown_ + nonFinite_ + missing_ > 0)
      ROS_WARN_THROTTLE(2.0,
                        "instrument_kinematics: dropped so far: %lu messages with names and "
                        "positions of different lengths, %lu unknown joint names, %lu non-finite "
                        "values, %lu missing joints (previous value kept)",
                        malformed_, unknown_, nonFinite_, missing_);
    if (!ok) return;
    chain_.forward(q_, poses_);
    const Eigen::Isometry3d& tip = poses_[chain_.tipLink()];

    geometry_msgs::PoseStamped pose;
    pose.header.stamp = stamp;
    pose.header.frame_id = world_;
    pose.pose = poseMsg(tip);
    pose_.publish(pose);

    const Eigen::Matrix<double, 6, 1> twist = chain_.tipJacobian(q_) * qd_;
    geometry_msgs::TwistStamped tw;
    tw.header = pose.header;
    tw.twist.linear.x = twist[0];
    tw.twist.linear.y = twist[1];
    tw.twist.linear.z = twist[2];
    tw.twist.angular.x = twist[3];
    tw.twist.angular.y = twist[4];
    tw.twist.angular.z = twist[5];
    twist_.publish(tw);

    if (jaw_ >= 0) {
      sensor_msgs::JointState jaw;
      jaw.header = pose.header;
      jaw.name = {"jaw"};
      jaw.position = {q_[jaw_]};
      jaw.velocity = {qd_[jaw_]};
      jawPub_.publish(jaw);
    }

    if (publishTf_) {
      transforms_.clear();
      for (const auto& j : chain_.joints())
        if (j.variable >= 0)
          transforms_.push_back(stampedTransform(chain_.jointTransform(j, q_), chain_.links()[j.parentLink],
                                             chain_.links()[j.childLink], stamp));
      tf_.sendTransform(transforms_);
    }
  }

  kin::Chain chain_;
  bool publishTf_;
  Eigen::VectorXd q_, qd_;
  std::vector<bool> seen_;
  std::vector<Eigen::Isometry3d> poses_;
  std::vector<geometry_msgs::TransformStamped> transforms_;
  int jaw_ = -1;
  std::string world_;
  ros::Time lastStamp_;
  bool haveStamp_ = false;
  unsigned long malformed_ = 0, unknown_ = 0, nonFinite_ = 0, missing_ = 0;
  ros::Publisher pose_, twist_, jawPub_;
  ros::Subscriber sub_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster staticTf_;
};

}  // namespace
}  // namespace tt::nodes

int main(int argc, char** argv) {
  ros::init(argc, argv, "instrument_kinematics");
  ros::NodeHandle nh, pn("~");
  try {
    tt::nodes::InstrumentKinematics node(nh, pn);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("instrument_kinematics: %s", e.what());
    return 2;
  }
  return 0;
}
