#pragma once
// A scene file (YAML) describes one simulation: mesh, materials, fibres, force models,
// integrator, boundary conditions, loads, run length and outputs. loadScene validates it
// strictly and builds only what it lists. See docs/scene_format.md.
#include <memory>
#include <optional>
#include <string>
#include <vector>

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

// Instrument-tissue contact (scene key `contact`), read by the contact library
// (tissue_trainer_contact). Plain numbers only: the scene knows nothing of Bullet.
struct ContactSettings {
  double stiffness = 200.0;        // penalty k_c per contact point (N/m)
  // > 0: penalties per surface node inside the tool instead, k_A times the node's area (N/m^3)
  double stiffnessPerArea = 0.0;
  double damping = 0.0;            // normal damping per contact point (N s/m; N s/m^3 with k_A)
  double graspStiffness = 100.0;   // spring from each grasped node to the tip (N/m)
  double graspJawAngle = 0.1;      // jaw opening (rad) below which the jaws grasp
  double graspRadius = 0.006;      // nodes within this distance of the jaw centre are grasped (m)
  int graspMaxNodes = 12;          // at most this many (the nearest) nodes per grasp
  // The stiffness K sent with f0 to the haptic side: the penalties' alone (the tissue held
  // fixed), or each penalty in series with the tissue's stiffness at its contact point, so the
  // felt stiffness follows the tissue's (a stiffening, beating wall feels stiffer at systole).
  bool tissueInSeries = false;
  // The tool the contact sees is a proxy that follows the device's tip at most this fast in
  // simulated time (m/s), so a frame that comes late never finds the tool far inside the
  // tissue; see tool_proxy.h. 0.1 m/s: above the fastest motion of the shipped task scripts
  // (0.087 m/s) and 1 cm in the longest frame of the simulation node's default (0.1 s).
  double toolMaxSpeed = 0.1;
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

class YamlEntry;
// The nodes a selection names: {box: {min, max}}, {plane: {point, normal, tolerance}},
// {nodes: [indices]} (rest positions). An empty result is an error at the entry.
std::vector<int> selectNodes(const YamlEntry& spec, const Mesh& mesh);
// The elements (numbered tets first, then hexes) a region names: `all`, {box: {min, max}}
// (element centroids at rest) or {elements: [indices]}; sorted, each once. A box that holds no
// centroid is an error at the entry.
std::vector<int> regionElements(const YamlEntry& region, const Mesh& mesh);

}  // namespace tt
