#pragma once
// What the simulation node reports about the tissue after each frame (its status message):
// the frame's measurements (scene_runner.h's FrameLog: energies, volume, displacement) and the
// strain summary (model/strain.h).
#include "tissue_trainer/core/model/strain.h"
#include "tissue_trainer/core/scene/scene_runner.h"

namespace tt {

struct FrameStatus {
  FrameLog frame;
  StrainSummary strain;
};

class FrameMeter {
 public:
  FrameMeter() = default;
  explicit FrameMeter(const System& system);

  FrameStatus measure(const System& system, int frame, const StepReport& step,
                      double damageStrain) const;
};

}  // namespace tt
