#pragma once
// Collision shapes of the instrument, each in its own link frame (as URDF collision
// elements): the shaft as a cylinder or capsule, the jaws as boxes or spheres. Cylinders and
// capsules run along the local z axis, centred on the origin (URDF convention).
#include <Eigen/Geometry>
#include <string>

namespace tt {

struct ToolShape {
  enum class Type { kSphere, kCapsule, kCylinder, kBox };
  Type type = Type::kSphere;
  double radius = 0.0;                           // sphere, capsule, cylinder (m)
  double length = 0.0;                           // capsule (between the cap centres), cylinder (m)
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // box edge lengths (m)
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();  // shape pose in its link frame
  std::string link;                              // the link that carries it
  bool jaw = false;                              // part of a jaw: counts for grasping
};

}  // namespace tt
