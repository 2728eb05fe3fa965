#pragma once
// A scene file (YAML) describes one simulation: mesh, materials, fibres, force models,
// integrator, boundary conditions, loads, run length and outputs. loadScene validates it
// strictly and builds only what it lists. See README "Scene format".
#include <memory>
#include <string>
#include <vector>

#include "tissue_trainer/core/integrate/integrator.h"
#include "tissue_trainer/core/system.h"

namespace tt {

struct SceneOutput {
  int vtuEvery = 0;    // write a VTU file every N frames (0: no VTU series)
  bool csv = false;    // write the per-frame CSV log
};

struct Scene {
  std::string file;
  std::string name;
  System system;
  std::unique_ptr<Integrator> integrator;
  double frameTime = 0.01;  // s, one integrator advance() per frame
  double duration = 1.0;    // s
  SceneOutput output;
  std::vector<std::string> notes;  // what the loader noticed (ignored elements, repairs)
};

// Throws InputError ("FILE:LINE: key.path: what was expected") on any problem.
Scene loadScene(const std::string& path);

}  // namespace tt
