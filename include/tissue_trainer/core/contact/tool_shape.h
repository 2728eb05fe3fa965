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

// How deep the point p (world) lies inside the shape posed at `pose` (world pose of the shape,
// offset included): true when inside, with the depth to the nearest surface point (m, > 0)
// and the outward unit normal there (the direction that pushes p out by the shortest way).
// False on or outside the surface.
bool penetration(const ToolShape& shape, const Eigen::Isometry3d& pose, const Eigen::Vector3d& p,
                 double& depth, Eigen::Vector3d& outward);

// How far the point p (world), inside the shape posed at `pose`, must move along the unit
// direction u to leave it (m, > 0): the far end of the ray p + s u in the convex shape. False
// when p is not inside.
bool exitDistance(const ToolShape& shape, const Eigen::Isometry3d& pose, const Eigen::Vector3d& p,
                  const Eigen::Vector3d& u, double& distance);

}  // namespace tt
