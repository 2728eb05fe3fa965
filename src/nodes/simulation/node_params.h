#pragma once
// Strict reading of private node parameters: a missing optional parameter takes its default;
// a present one of the wrong type or range logs one line naming it and what was expected,
// and the function returns false (the node then exits non-zero).
#include <ros/node_handle.h>

#include <string>

namespace tt_nodes {

bool readNumber(const ros::NodeHandle& nh, const std::string& name, double& value, double min,
                bool exclusiveMin);
bool readInteger(const ros::NodeHandle& nh, const std::string& name, int& value, int min);
// required: a missing parameter is an error too.
bool readString(const ros::NodeHandle& nh, const std::string& name, std::string& value,
                bool required);

}  // namespace tt_nodes
