#pragma once
// What the organ-scale benchmarks share: the liver palpation scene (config/scenes/
// liver_palpation.yaml) on another mesh of the same liver, and the pose that presses the
// scripted operator's sphere into the liver's anterior face.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "common/bench_support.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace bench {

// liver.msh refined by TetGen to about `target` tets in workDir/liver_<target> (the volume
// bound adjusted by the count it gives); "" when tetgen is missing or fails.
std::string refinedLiver(const std::string& workDir, int target, int& tets);

// A change of the scene's text: `from` (which must be there) becomes `to`.
struct SceneEdit {
  std::string from, to;
};

// Writes the palpation scene with `mesh` (an absolute path) for its liver to `path`, with
// `edits` applied after; throws when the scene no longer holds the text one replaces.
void writeLiverSceneWithMesh(const std::string& mesh, const std::string& path,
                             const std::vector<SceneEdit>& edits = {});

// The reference of the benchmarks' step errors, and of the settling steps: Jacobi-PCG to 1e-10
// (a Cholesky factor would need BiCGSTAB and thousands of iterations where the pressed liver's
// matrix is indefinite).
BackwardEulerParams tightBackwardEuler();

// Lets the liver sag to rest under gravity (3 s in steps of 0.1 s, solved tightly; the mass
// damping and backward Euler's own damping settle it), then zeroes the velocity.
void sagToRest(System& system, BackwardEulerIntegrator& settle);

// A sphere of `radius` pressed `depth` into the highest point (z) of the liver within 2 cm
// (in x, y) of the trocar axis (x, y) = (-0.035, 0.075), from above as the scripted operator
// presses it.
Eigen::Isometry3d pressingPose(const System& system, double radius, double depth);

}  // namespace bench
}  // namespace tt
