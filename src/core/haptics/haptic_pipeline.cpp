#include "tissue_trainer/core/haptics/haptic_pipeline.h"

namespace tt {

HapticPipeline::HapticPipeline(const HapticPipelineOptions& options)
    : extrapolator_(options.extrapolation),
      safety_(options.safety),
      stats_(options.statsWindow, options.overrunThreshold) {}

Eigen::Vector3d HapticPipeline::tick(const Eigen::Vector3d& xDevice, double tNow, bool enabled) {
  stats_.record(tNow);
  requested_ = extrapolator_.force(xDevice, tNow);
  return safety_.step(requested_, tNow, extrapolator_.modelAge(tNow), enabled);
}

}  // namespace tt
