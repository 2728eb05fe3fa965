#include "tissue_trainer/core/scene/frame_meter.h"

namespace tt {

FrameMeter::FrameMeter(const System&) {}

FrameStatus FrameMeter::measure(const System& system, int frame, const StepReport& step,
                                double damageStrain) const {
  FrameStatus s;
  s.frame = measureFrame(system, frame, step);
  s.strain = measureStrain(system.mesh, system.state.x, damageStrain);
  return s;
}

}  // namespace tt
