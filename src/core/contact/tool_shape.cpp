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

// The far root s of |q + s u|^2 = r^2 (q inside the sphere of radius r about the origin).
double sphereExit(const Eigen::Vector3d& q, const Eigen::Vector3d& u, double r) {
  const double b = q.dot(u);
  return -b + std::sqrt(std::max(0.0, b * b - q.squaredNorm() + r * r));
}

// The far root s of |(q + s u)_xy|^2 = r^2, or infinity when u runs along z.
double radialExit(const Eigen::Vector3d& q, const Eigen::Vector3d& u, double r) {
  const Eigen::Vector2d qxy = q.head<2>(), uxy = u.head<2>();
  const double a = uxy.squaredNorm();
  if (a < 1e-30) return HUGE_VAL;
  const double b = qxy.dot(uxy);
  return (-b + std::sqrt(std::max(0.0, b * b - a * (qxy.squaredNorm() - r * r)))) / a;
}

// The slab exit along one axis: where q_i + s u_i reaches the face at +-half, or infinity.
double slabExit(double q, double u, double half) {
  if (u == 0.0) return HUGE_VAL;
  return ((u > 0.0 ? half : -half) - q) / u;
}

double localExit(const ToolShape& s, const Eigen::Vector3d& q, const Eigen::Vector3d& u) {
  switch (s.type) {
    case ToolShape::Type::kSphere:
      return sphereExit(q, u, s.radius);
    case ToolShape::Type::kCapsule: {
      const double half = 0.5 * s.length, side = radialExit(q, u, s.radius);
      const double z = q.z() + side * u.z();
      if (std::abs(z) <= half) return side;
      return sphereExit(q - Eigen::Vector3d(0, 0, z > 0.0 ? half : -half), u, s.radius);
    }
    case ToolShape::Type::kCylinder:
      return std::min(radialExit(q, u, s.radius), slabExit(q.z(), u.z(), 0.5 * s.length));
    case ToolShape::Type::kBox: {
      double exit = HUGE_VAL;
      for (int i = 0; i < 3; ++i) exit = std::min(exit, slabExit(q[i], u[i], 0.5 * s.size[i]));
      return exit;
    }
  }
  return 0.0;
}

}  // namespace

bool exitDistance(const ToolShape& shape, const Eigen::Isometry3d& pose, const Eigen::Vector3d& p,
                  const Eigen::Vector3d& u, double& distance) {
  double depth = 0.0;
  Eigen::Vector3d unused;
  const Eigen::Vector3d q = pose.inverse() * p;
  if (!localPenetration(shape, q, depth, unused)) return false;
  distance = localExit(shape, q, pose.linear().transpose() * u);
  return distance > 0.0 && std::isfinite(distance);
}

bool penetration(const ToolShape& shape, const Eigen::Isometry3d& pose, const Eigen::Vector3d& p,
                 double& depth, Eigen::Vector3d& outward) {
  Eigen::Vector3d localOutward;
  if (!localPenetration(shape, pose.inverse() * p, depth, localOutward)) return false;
  outward = pose.linear() * localOutward;
  return true;
}

}  // namespace tt
