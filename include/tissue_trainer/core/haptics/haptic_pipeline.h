#pragma once
// The haptic bridge's per-tick logic without ROS: contact models go into a ForceExtrapolator,
// each tick's force goes through the SafetyFilter, and the tick times feed a LoopStatsWindow.
// The ROS node only moves messages in and out.
#include <Eigen/Core>

#include "tissue_trainer/core/haptics/force_extrapolator.h"
#include "tissue_trainer/core/haptics/loop_stats.h"
#include "tissue_trainer/core/haptics/safety_filter.h"

namespace tt {

struct HapticPipelineOptions {
  ExtrapolatorOptions extrapolation;
  SafetyOptions safety;
  std::size_t statsWindow = 2000;      // ticks kept for the loop statistics
  double overrunThreshold = 0.0015;    // s: a longer tick period is an overrun
};

class HapticPipeline {
 public:
  explicit HapticPipeline(const HapticPipelineOptions& options = {});

  // A model taken in at tReceive with the device at xDevice (see ForceExtrapolator::submit).
  ModelVerdict submit(const ContactModel& model, double tReceive, const Eigen::Vector3d& xDevice) {
    return extrapolator_.submit(model, tReceive, xDevice);
  }

  // Device position (m), tick time (s), enable/deadman; returns the force to send (N).
  Eigen::Vector3d tick(const Eigen::Vector3d& xDevice, double tNow, bool enabled);

  const Eigen::Vector3d& requested() const { return requested_; }  // before the safety filter
  const ForceExtrapolator& extrapolator() const { return extrapolator_; }
  const SafetyFilter& safety() const { return safety_; }
  const LoopStatsWindow& loopStats() const { return stats_; }

 private:
  ForceExtrapolator extrapolator_;
  SafetyFilter safety_;
  LoopStatsWindow stats_;
  Eigen::Vector3d requested_ = Eigen::Vector3d::Zero();
};

}  // namespace tt
