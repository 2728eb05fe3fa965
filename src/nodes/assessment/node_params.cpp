#include "node_params.h"

#include <stdexcept>

#include "../common/param_reader.h"

namespace tt {

AssessmentNodeParams readAssessmentNodeParams(const ros::NodeHandle& nh) {
  const tt_nodes::ParamReader p(nh);
  // The ranges of the metric settings are checked once, by the core (validate()).
  AssessmentNodeParams out;
  AssessmentSettings& s = out.settings;
  s.forceThreshold = p.number("force_threshold", s.forceThreshold);
  s.movementSpeedStart = p.number("movement_speed_start", s.movementSpeedStart);
  s.movementSpeedStop = p.number("movement_speed_stop", s.movementSpeedStop);
  s.resampleRate = p.number("resample_rate", s.resampleRate);
  s.smoothingTime = p.number("smoothing_time", s.smoothingTime);
  s.maxGap = p.number("max_gap", s.maxGap);
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    throw tt_nodes::ParamError(p.qualified("") + "/" + e.what());
  }
  out.summaryRate = p.number("summary_rate", out.summaryRate, 1e-3, 100.0);
  out.outputDir = p.text("output_dir", out.outputDir);
  if (out.outputDir.empty())
    throw tt_nodes::ParamError(p.qualified("output_dir") + ": expected a non-empty directory path");
  return out;
}

}  // namespace tt
