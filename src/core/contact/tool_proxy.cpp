#include "tissue_trainer/core/contact/tool_proxy.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tt {

ToolProxy::ToolProxy(double maxSpeed) : maxSpeed_(maxSpeed) {
  if (!(std::isfinite(maxSpeed) && maxSpeed > 0.0))
    throw std::invalid_argument("tool proxy: expected a finite speed > 0 (m/s), got " + std::to_string(maxSpeed));
}

const Eigen::Vector3d& ToolProxy::follow(const Eigen::Vector3d& target, double step) {
  if (!target.allFinite()) throw std::invalid_argument("tool proxy: the target is not finite");
  if (!(std::isfinite(step) && step >= 0.0))
    throw std::invalid_argument("tool proxy: expected a finite step >= 0, got " + std::to_string(step));
  if (!placed_) {
    position_ = target;
    placed_ = true;
  } else {
    const Eigen::Vector3d gap = target - position_;
    const double distance = gap.norm();
    const double reach = maxSpeed_ * step;
    position_ = distance <= reach ? target : Eigen::Vector3d(position_ + gap * (reach / distance));
  }
  lag_ = (target - position_).norm();
  return position_;
}

}  // namespace tt
