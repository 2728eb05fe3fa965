#pragma once
// The trocar chain of config/instruments/grasper.urdf, built by hand for the core tests (the
// URDF itself is read by the nodes with urdfdom and checked in test/integration).
#include <cmath>

#include "tissue_trainer/core/kinematics/chain.h"

namespace tt::kin::test {

inline const Eigen::Vector3d kTrocar(-0.035, 0.075, 0.20);

inline Chain grasperChain() {
  auto joint = [](const char* name, const char* parent, const char* child, JointType type,
                  Eigen::Vector3d axis, double lo, double hi) {
    JointSpec j;
    j.name = name;
    j.parent = parent;
    j.child = child;
    j.type = type;
    j.axis = axis;
    j.lower = lo;
    j.upper = hi;
    return j;
  };
  using V = Eigen::Vector3d;
  JointSpec mount = joint("trocar_mount", "world", "trocar", JointType::kFixed, V::UnitX(), 0, 0);
  mount.origin = Eigen::Translation3d(kTrocar) * Eigen::AngleAxisd(M_PI, V::UnitY());
  JointSpec upper = joint("jaw_upper_hinge", "instrument_tip", "jaw_upper", JointType::kRevolute,
                          -V::UnitX(), 0, 0.6);
  upper.mimic = "jaw";
  upper.multiplier = 0.5;
  JointSpec lower = joint("jaw_lower_hinge", "instrument_tip", "jaw_lower", JointType::kRevolute,
                          V::UnitX(), 0, 0.6);
  lower.mimic = "jaw";
  lower.multiplier = 0.5;
  // Given out of order on purpose: the chain sorts them.
  return Chain("world",
               {upper, mount,
                joint("yaw", "trocar", "yaw_link", JointType::kRevolute, V::UnitY(), -1, 1),
                joint("pitch", "yaw_link", "pitch_link", JointType::kRevolute, V::UnitX(), -1, 1),
                joint("roll", "pitch_link", "roll_link", JointType::kRevolute, V::UnitZ(), -3.14159, 3.14159),
                joint("insertion", "roll_link", "shaft", JointType::kPrismatic, V::UnitZ(), 0, 0.25),
                joint("tip_mount", "shaft", "instrument_tip", JointType::kFixed, V::UnitX(), 0, 0),
                joint("jaw", "instrument_tip", "jaw_actuator", JointType::kRevolute, -V::UnitX(), 0, 1.2),
                lower},
               "instrument_tip");
}

// The trocar geometry by hand: the shaft direction in world for yaw and pitch.
inline Eigen::Vector3d shaftDirection(double yaw, double pitch) {
  return {-std::cos(pitch) * std::sin(yaw), -std::sin(pitch), -std::cos(pitch) * std::cos(yaw)};
}

}  // namespace tt::kin::test
