#include "tissue_trainer/core/operator/virtual_hand.h"

#include <cmath>
#include <stdexcept>

namespace tt {

VirtualHand::VirtualHand(const HandGains& gains, const Eigen::Vector3d& position) : gains_(gains) {
  if (!(std::isfinite(gains.mass) && gains.mass > 0.0))
    throw std::invalid_argument("virtual hand: expected a positive finite mass (kg)");
  if (!(std::isfinite(gains.stiffness) && gains.stiffness > 0.0))
    throw std::invalid_argument("virtual hand: expected a positive finite stiffness (N/m)");
  if (!(std::isfinite(gains.damping) && gains.damping >= 0.0))
    throw std::invalid_argument("virtual hand: expected a non-negative finite damping (N s/m)");
  if (!position.allFinite()) throw std::invalid_argument("virtual hand: non-finite position");
  reset(position);
}

void VirtualHand::reset(const Eigen::Vector3d& position) {
  x_ = position;
  v_.setZero();
}

void VirtualHand::step(const Eigen::Vector3d& target, const Eigen::Vector3d& targetVelocity,
                       const Eigen::Vector3d& force, double dt) {
  if (!(std::isfinite(dt) && dt > 0.0) || !target.allFinite()) return;
  const Eigen::Vector3d f = force.allFinite() ? force : Eigen::Vector3d::Zero();
  const Eigen::Vector3d vt = targetVelocity.allFinite() ? targetVelocity : Eigen::Vector3d::Zero();
  const double m = gains_.mass, k = gains_.stiffness, c = gains_.damping;
  // (m + dt c + dt^2 k) v' = m v + dt (k (target - x) + c vt + f)
  v_ = (m * v_ + dt * (k * (target - x_) + c * vt + f)) / (m + dt * c + dt * dt * k);
  x_ += dt * v_;
}

}  // namespace tt
