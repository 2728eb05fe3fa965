#pragma once
// Instrument collision shapes from a URDF (the /robot_description): every collision element
// of every link, in its link's frame. Spheres, boxes and cylinders are kept (cylinders as
// cylinders); meshes are skipped. Links whose name contains "jaw" are jaws (for grasping).
#include <string>
#include <vector>

#include "tissue_trainer/core/contact/tool_shape.h"

namespace tt_nodes {

// Throws std::runtime_error with one line when the XML is not a URDF.
// `skipped` gets one note per collision element that was not used.
std::vector<tt::ToolShape> toolShapesFromUrdf(const std::string& xml,
                                              std::vector<std::string>* skipped = nullptr);

}  // namespace tt_nodes
