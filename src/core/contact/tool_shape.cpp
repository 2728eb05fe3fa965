#include "tissue_trainer/core/contact/tool_shape.h"

#include <algorithm>
#include <cmath>

namespace tt {
namespace {

// The unit vector along v, or +z where v has no direction (p at a sphere's centre or on a
// capsule's axis: every way out is as short).
Eigen::Vector3d directionOr(const Eigen::Vector3d& v) {
  const double n = v.norm();
  return n > 1e-15 ? Eigen::Vector3d(v / n) : Eigen::Vector3d::UnitZ();
}

// In the shape's own frame (cylinders and capsules along z, centred on the origin).
bool localPenetration(const ToolShape& s, const Eigen::Vector3d& q, double& depth,
                      Eigen::Vector3d& outward) {
  switch (s.type) {
    case ToolShape::Type::kSphere:
      depth = s.radius - q.norm();
      outward = directionOr(q);
      break;
    case ToolShape::Type::kCapsule: {
      const double half = 0.5 * s.length;
      const Eigen::Vector3d fromAxis = q - Eigen::Vector3d(0, 0, std::clamp(q.z(), -half, half));
      depth = s.radius - fromAxis.norm();
      outward = directionOr(fromAxis);
      break;
    }
    case ToolShape::Type::kCylinder: {
      const double radial = std::hypot(q.x(), q.y());
      const double toSide = s.radius - radial, toCap = 0.5 * s.length - std::abs(q.z());
      if (toSide < toCap) {
        depth = toSide;
        outward = directionOr(Eigen::Vector3d(q.x(), q.y(), 0.0));
      } else {
        depth = toCap;
        outward = Eigen::Vector3d(0, 0, q.z() < 0.0 ? -1.0 : 1.0);
      }
      break;
    }
    case ToolShape::Type::kBox: {
      const Eigen::Vector3d toFace = 0.5 * s.size - q.cwiseAbs();
      Eigen::Index axis = 0;
      depth = toFace.minCoeff(&axis);
      outward = Eigen::Vector3d::Zero();
      outward[axis] = q[axis] < 0.0 ? -1.0 : 1.0;
      break;
    }
  }
  return depth > 0.0;
}

}  // namespace

bool penetration(const ToolShape& shape, const Eigen::Isometry3d& pose, const Eigen::Vector3d& p,
                 double& depth, Eigen::Vector3d& outward) {
  Eigen::Vector3d localOutward;
  if (!localPenetration(shape, pose.inverse() * p, depth, localOutward)) return false;
  outward = pose.linear() * localOutward;
  return true;
}

}  // namespace tt
