#pragma once
// What the simulation node reports about the tissue after each frame (its status message):
// the frame's measurements (scene_runner.h's FrameLog: energies, volume, displacement,
// barycentre) and the strain summary (model/strain.h), as measureFrame and measureStrain give
// them, in one pass over the tets with the rest data kept from the construction (each tet's
// inverse rest edge matrix and rest volume), so that a frame costs a constant amount of work
// per tet and per node.
#include <Eigen/Core>
#include <vector>

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
  // Keeps the rest data of system's mesh; measure() takes that system (same mesh and masses).
  explicit FrameMeter(const System& system);

  // Throws std::invalid_argument for a system of another size than the one it was built for.
  FrameStatus measure(const System& system, int frame, const StepReport& step,
                      double damageStrain) const;

 private:
  struct RestTet {
    Eigen::Matrix3d edgesInverse;  // Dm^-1, Dm = [X1 - X0, X2 - X0, X3 - X0]
    double volume = 0.0;           // det(Dm) / 6
    bool strained = false;         // its strain is measured (not degenerate at rest)
  };
  std::vector<RestTet> tets_;
  int numNodes_ = 0, numHexes_ = 0;
  double restVolume_ = 0.0;                             // tets and hexes (m^3)
  Eigen::Vector3d massPerAxis_ = Eigen::Vector3d::Zero();  // sum of the masses per axis
};

}  // namespace tt
