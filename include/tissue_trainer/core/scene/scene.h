#pragma once
// A scene file (YAML) describes one simulation: mesh, materials, fibres, force models,
// integrator, boundary conditions, loads, run length and outputs. loadScene validates it
// strictly and builds only what it lists. See docs/scene_format.md.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tissue_trainer/core/contact/contact_settings.h"
#include "tissue_trainer/core/integrate/integrator.h"
#include "tissue_trainer/core/mesh/embedding.h"
#include "tissue_trainer/core/system.h"

namespace tt {

// Stop a run early ("Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.2: the kinetic
// energy dropping below a threshold E_k,min): after the first frame that ends at t >= notBefore
// with a kinetic energy below `below`.
struct KineticEnergyStop {
  double below = 0.0;      // J
  double notBefore = 0.0;  // s
};

struct SceneOutput {
  int vtuEvery = 0;    // write a VTU file every N frames (0: no VTU series)
  bool csv = false;    // write the per-frame CSV log
};

// A finer triangle surface (scene key `render_surface`) embedded into the tet mesh: its
// vertices follow the deformed tets through fixed barycentric weights.
struct RenderSurface {
  std::string file;
  Eigen::Matrix3Xd rest;            // rest vertices (m, world)
  std::vector<Triangle> triangles;
  Embedding embedding;
};

struct Scene {
  std::string file;
  std::string name;
  System system;
  std::unique_ptr<Integrator> integrator;
  double frameTime = 0.01;  // s, one integrator advance() per frame
  double duration = 1.0;    // s, t_max
  // Longest frame the simulation node takes to keep up with wall time (run.max_frame_time,
  // >= frameTime); unset: the node's default (real_time_clock.h, docs/scene_format.md).
  std::optional<double> maxFrameTime;
  // Simulated time the simulation node steps the scene before it starts in real time, so that
  // a session starts with the tissue at rest under its loads (run.settle_time; 0: none).
  double settleTime = 0.0;
  std::optional<KineticEnergyStop> kineticEnergyStop;  // only when `run` lists it
  SceneOutput output;
  std::optional<ContactSettings> contact;         // only when the scene lists `contact`
  std::optional<RenderSurface> renderSurface;     // only when the scene lists `render_surface`
  // Nodes of `boundary.fixed` entries with `jaw: true` (fixed on all axes): the nodes a landmark
  // fit's jaw transform moves (FitParams::jawNodes); sorted, each once.
  std::vector<int> jawNodes;
  std::vector<std::string> notes;  // what the loader noticed (ignored elements, repairs)
};

// Throws InputError ("FILE:LINE: key.path: what was expected") on any problem.
Scene loadScene(const std::string& path);

}  // namespace tt
