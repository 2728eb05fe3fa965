#pragma once
// tissue_trainer/ContactModel (ROS) -> tt::ContactModel (core).
#include "tissue_trainer/ContactModel.h"
#include "tissue_trainer/core/haptics/contact_model.h"

namespace tt_nodes {

tt::ContactModel toCore(const tissue_trainer::ContactModel& msg);

}  // namespace tt_nodes
