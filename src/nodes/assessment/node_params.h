#pragma once
// The assessment node's private parameters, each checked for its type and range.
#include <ros/node_handle.h>

#include <string>

#include "tissue_trainer/core/assess/assessment_settings.h"

namespace tt {

struct AssessmentNodeParams {
  AssessmentSettings settings;
  std::string outputDir = "assessment";  // relative to the node's working directory (ROS_HOME)
  double summaryRate = 1.0;              // Hz
};

// Throws tt_nodes::ParamError "/node/KEY: expected ..., got ..." for the first bad one.
AssessmentNodeParams readAssessmentNodeParams(const ros::NodeHandle& privateNh);

}  // namespace tt
