#pragma once
// The tool the tissue contact sees: a proxy point that follows the device's tip at a bounded
// speed in simulated time. When the simulation falls behind (a long first frame, a frame
// capped at the maximum step) the device may have moved centimetres in wall time; the proxy
// moves at most maxSpeed * step toward it per frame, so the tissue meets the tool as it would
// meet a tool moving at that speed, never a jump deep into it. Where the device stops, the
// proxy reaches it. ROS-free, no Bullet: the simulation node shifts the tool's poses by
// (proxy - tip) before TissueContact::setTool.
#include <Eigen/Core>

namespace tt {

class ToolProxy {
 public:
  // Throws std::invalid_argument unless maxSpeed is finite and > 0 (m/s).
  explicit ToolProxy(double maxSpeed);

  // Moves the proxy toward `target` (m) by at most maxSpeed * step (step: simulated s, >= 0)
  // and returns its position. The first call after construction or reset() places it at the
  // target. A non-finite target or step throws std::invalid_argument and changes nothing.
  const Eigen::Vector3d& follow(const Eigen::Vector3d& target, double step);
  // Forget the position: the next follow() places the proxy (a new scene, a reset).
  void reset() { placed_ = false; }

  bool placed() const { return placed_; }
  const Eigen::Vector3d& position() const { return position_; }
  double lag() const { return lag_; }  // distance from the proxy to the last target (m)
  double maxSpeed() const { return maxSpeed_; }

 private:
  double maxSpeed_;
  bool placed_ = false;
  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
  double lag_ = 0.0;
};

}  // namespace tt
