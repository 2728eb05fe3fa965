#pragma once
// Eigen poses to geometry_msgs (tf2_eigen is not packaged here).
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>

#include <Eigen/Geometry>

namespace tt::nodes {

inline geometry_msgs::Pose poseMsg(const Eigen::Isometry3d& t) {
  const Eigen::Quaterniond q(t.linear());
  geometry_msgs::Pose p;
  p.position.x = t.translation().x();
  p.position.y = t.translation().y();
  p.position.z = t.translation().z();
  p.orientation.x = q.x();
  p.orientation.y = q.y();
  p.orientation.z = q.z();
  p.orientation.w = q.w();
  return p;
}

inline geometry_msgs::Transform transformMsg(const Eigen::Isometry3d& t) {
  const geometry_msgs::Pose p = poseMsg(t);
  geometry_msgs::Transform out;
  out.translation.x = p.position.x;
  out.translation.y = p.position.y;
  out.translation.z = p.position.z;
  out.rotation = p.orientation;
  return out;
}

}  // namespace tt::nodes
