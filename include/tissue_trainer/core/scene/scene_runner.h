#pragma once
// Runs a loaded scene headless ("Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.2):
// one integrator advance per frame, a CSV log line per frame and a VTU file every N frames
// (with a ParaView .pvd collection), until t_max (the duration), the kinetic energy falls
// below the scene's threshold, an interrupt is requested or a step fails.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {

struct FrameLog {
  int frame = 0;
  double time = 0.0;
  double kineticEnergy = 0.0;
  double elasticEnergy = 0.0;
  double loadEnergy = 0.0;       // potential of body loads (gravity), J
  double volumeRatio = 1.0;      // total deformed volume / total rest volume
  double maxDisplacement = 0.0;  // m
  Eigen::Vector3d barycentre = Eigen::Vector3d::Zero();  // centre of mass (m)
  double volume = 0.0;                // deformed volume of every tet and hex (m^3)
  std::vector<double> observables;  // the models' observables in scene order (ForceModel)
  StepReport step;
  GuardFrame guard;  // what the stability guard did in the frame (nothing without one)
};

struct RunOptions {
  double duration = -1.0;   // s; negative: the scene's duration
  std::string outDir;       // empty: write nothing
  std::function<void(const FrameLog&)> onFrame;  // progress, called after every frame
  // Asked after every frame; true ends the run there (an interrupt), outputs written.
  std::function<bool()> stopRequested;
};

// Why a run ended.
enum class StopReason { kDuration, kKineticEnergy, kInterrupt, kFailure };
const char* stopReasonName(StopReason reason);  // duration, kinetic_energy, interrupt, failure

struct RunSummary {
  int frames = 0;
  double simulatedTime = 0.0;
  double wallSeconds = 0.0;
  double stepWallMedian = 0.0, stepWallMax = 0.0;  // s per frame
  FrameLog last;
  bool ok = true;
  std::string failure;
  StopReason stop = StopReason::kDuration;
  GuardStats guard;                // frames = 0 when the scene runs without the guard
  std::vector<std::string> files;  // written, in order
};

FrameLog measureFrame(const System& system, int frame, const StepReport& step);
RunSummary runScene(Scene& scene, const RunOptions& options);

struct SettleSummary {
  int frames = 0;
  double simulatedTime = 0.0;  // s advanced
  double wallSeconds = 0.0;
  bool ok = true;
  std::string failure;  // the first failed frame's (its restored state is kept)
};

// Steps the scene for `seconds` of simulated time in frames of at most `frame` s, with nothing
// else changing: the settling of scene key run.settle_time, so that a session starts with the
// tissue at rest under its loads instead of dropping at the trainee's first touch. Stops at
// the first failed frame. Throws std::invalid_argument unless frame > 0 and seconds >= 0.
SettleSummary settleScene(Scene& scene, double seconds, double frame);

}  // namespace tt
