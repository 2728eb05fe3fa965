#include "contact_conversion.h"

namespace tt_nodes {

tt::ContactModel toCore(const tissue_trainer::ContactModel& msg) {
  tt::ContactModel m;
  m.stamp = msg.header.stamp.toSec();
  m.sequence = msg.sequence;
  m.inContact = msg.in_contact;
  m.x0 = Eigen::Vector3d(msg.tool_position.x, msg.tool_position.y, msg.tool_position.z);
  m.f0 = Eigen::Vector3d(msg.force.x, msg.force.y, msg.force.z);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.K(r, c) = msg.stiffness[3 * r + c];  // row-major
  m.simTime = msg.simulation_time;
  return m;
}

}  // namespace tt_nodes
