#pragma once
// The instrument's URDF (read with urdfdom through urdf::Model) as a core kinematic chain,
// and the strict reading of node parameters. Shared by instrument_kinematics and operator.
#include <ros/node_handle.h>

#include <stdexcept>
#include <string>

#include "tissue_trainer/core/kinematics/chain.h"

namespace tt::nodes {

// Throws std::runtime_error (one line) when the XML is not a URDF, a joint is floating or
// planar, or the tree is malformed. The chain's root is the URDF root link.
kin::Chain chainFromUrdf(const std::string& xml, const std::string& tipLink);

// Reads the URDF text from the parameter `param` (e.g. "/robot_description").
kin::Chain chainFromParameter(const ros::NodeHandle& nh, const std::string& param,
                              const std::string& tipLink);

// Strict private parameters: absent -> the default; present with the wrong type or out of
// range -> std::runtime_error "~name: expected ..., got ...".
std::string stringParam(const ros::NodeHandle& pn, const std::string& name, const std::string& fallback);
std::string requiredStringParam(const ros::NodeHandle& pn, const std::string& name);
double numberParam(const ros::NodeHandle& pn, const std::string& name, double fallback,
                   double minimum, double maximum);
bool boolParam(const ros::NodeHandle& pn, const std::string& name, bool fallback);

}  // namespace tt::nodes
