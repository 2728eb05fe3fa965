#pragma once
// The assessment node's private parameters, each checked for its type and range.
#include <ros/node_handle.h>

#include <string>

#include "tissue_trainer/core/assess/assessment_settings.h"
#include "tissue_trainer/core/assess/skill_score.h"

namespace tt {

struct AssessmentNodeParams {
  AssessmentSettings settings;
  std::string outputDir = "assessment";  // relative to the node's working directory (ROS_HOME)
  double summaryRate = 1.0;              // Hz
  bool scored = false;                   // ~reference_bands is not "none"
  ReferenceBands bands;                  // read from ~reference_bands
};

// Throws tt_nodes::ParamError "/node/KEY: expected ..., got ..." for the first bad one.
AssessmentNodeParams readAssessmentNodeParams(const ros::NodeHandle& privateNh);

}  // namespace tt
