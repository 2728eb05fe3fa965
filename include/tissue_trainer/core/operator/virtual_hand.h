#pragma once
// The scripted operator's hand: a point mass on a spring-damper pulled toward the scripted
// target (and its velocity) and pushed by the force the device commands (N, world):
//   m a = k (target - x) + c (targetVelocity - v) + f
// Integrated semi-implicitly: the spring and damper implicitly (linearised backward Euler,
// stable for any gains and step), the external force explicitly, then x += dt v.
// At rest under a constant force the hand settles at target + f / k.
#include <Eigen/Core>

namespace tt {

struct HandGains {
  double mass = 0.2;        // kg
  double stiffness = 400;   // N/m (a relaxed human arm holding an instrument: 200-1000)
  double damping = 18;      // N s/m (about critical: 2 sqrt(k m) = 17.9)
};

class VirtualHand {
 public:
  // Throws std::invalid_argument unless every gain is finite, mass and stiffness positive and
  // damping non-negative, and the position finite.
  VirtualHand(const HandGains& gains, const Eigen::Vector3d& position);

  // Advances by dt (s, positive and finite, otherwise nothing happens). A non-finite force
  // or target velocity counts as zero; a non-finite target leaves the hand where it is.
  void step(const Eigen::Vector3d& target, const Eigen::Vector3d& targetVelocity,
            const Eigen::Vector3d& force, double dt);

  void reset(const Eigen::Vector3d& position);
  const Eigen::Vector3d& position() const { return x_; }
  const Eigen::Vector3d& velocity() const { return v_; }
  const HandGains& gains() const { return gains_; }

 private:
  HandGains gains_;
  Eigen::Vector3d x_, v_;
};

}  // namespace tt
