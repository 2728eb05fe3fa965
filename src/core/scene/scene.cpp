#include "tissue_trainer/core/scene/scene.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>

#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/material/elastic_constants_reader.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/mesh/mesh_order.h"
#include "tissue_trainer/core/mesh/node_tags.h"
#include "tissue_trainer/core/mesh/quality.h"
#include "tissue_trainer/core/model/gravity.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/registry/selection.h"
#include "tissue_trainer/core/registry/yaml_file.h"
#include "tissue_trainer/core/registry/yaml_reader.h"
#include "scene_fibres.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

double lengthUnit(const YamlEntry& e) {
  const std::string unit = e.choice({"m", "cm", "mm"});
  return unit == "m" ? 1.0 : unit == "cm" ? 1e-2 : 1e-3;
}

TetSplit parseSplit(const YamlEntry& e) {
  const std::string s = e.choice({"five", "five_mirrored", "six", "six_mirrored", "none"});
  if (s == "none") return TetSplit::kNone;
  if (s == "five") return TetSplit::kFive;
  if (s == "five_mirrored") return TetSplit::kFiveMirrored;
  if (s == "six") return TetSplit::kSix;
  return TetSplit::kSixMirrored;
}

// The truncated ellipsoid of Land et al., "Verification of cardiac mechanics software" (2015),
// Sec. 2c(ii). The radii are in the mesh's length_unit; their defaults are the paper's
// geometry (mm) in that unit.
EllipsoidShape readEllipsoid(const YamlEntry& spec) {
  spec.expectMap({"generator", "cells_transmural", "cells_meridional", "cells_circumferential",
                  "endocardium", "epicardium", "base_z", "split", "length_unit", "scale",
                  "translate", "rotate_deg"});
  const double mm = 1e-3 / (spec.has("length_unit") ? lengthUnit(spec["length_unit"]) : 1.0);
  EllipsoidShape shape;
  shape.endoShort = 7 * mm, shape.endoLong = 17 * mm;
  shape.epiShort = 10 * mm, shape.epiLong = 20 * mm;
  shape.baseZ = 5 * mm;
  shape.transmural = spec.integerAtLeast("cells_transmural", 1, shape.transmural);
  shape.meridional = spec.integerAtLeast("cells_meridional", 2, shape.meridional);
  shape.circumferential = spec.integerAtLeast("cells_circumferential", 3, shape.circumferential);
  const auto radii = [&](const char* key, double& shortRadius, double& longRadius) {
    if (!spec.has(key)) return;
    const YamlEntry e = spec[key];
    if (e.size() != 2) e.fail("expected 2 radii [short, long] (the spheroid's r_s, r_l)");
    shortRadius = e[0].positive();
    longRadius = e[1].positive();
  };
  radii("endocardium", shape.endoShort, shape.endoLong);
  radii("epicardium", shape.epiShort, shape.epiLong);
  char text[200];
  if (!(shape.epiShort > shape.endoShort && shape.epiLong > shape.endoLong)) {
    std::snprintf(text, sizeof text,
                  "expected epicardial radii larger than the endocardial ones: [%g, %g] is not "
                  "outside [%g, %g]", shape.epiShort, shape.epiLong, shape.endoShort,
                  shape.endoLong);
    spec[spec.has("epicardium") ? "epicardium" : "endocardium"].fail(text);
  }
  if (spec.has("base_z")) {
    const YamlEntry e = spec["base_z"];
    shape.baseZ = e.number();
    if (!(shape.baseZ >= 0.0 && shape.baseZ < shape.endoLong)) {
      std::snprintf(text, sizeof text,
                    "expected 0 <= base_z < the endocardial long radius (%g), got %g",
                    shape.endoLong, shape.baseZ);
      e.fail(text);
    }
  } else if (!(shape.baseZ < shape.endoLong)) {
    std::snprintf(text, sizeof text,
                  "expected a long radius above the cut of the base (base_z %g), got %g",
                  shape.baseZ, shape.endoLong);
    spec["endocardium"].fail(text);
  }
  return shape;
}

// `ellipsoid` gets the shape of a truncated_ellipsoid generator.
Mesh generateMesh(const YamlEntry& spec, std::optional<EllipsoidShape>& ellipsoid) {
  const std::string type =
      spec["generator"].choice({"box", "cantilever", "spindle", "truncated_ellipsoid"});
  if (type == "truncated_ellipsoid") {
    ellipsoid = readEllipsoid(spec);
    const bool hexes = spec.has("split") && spec["split"].choice({"none", "six"}) == "none";
    return truncatedEllipsoid(*ellipsoid, hexes ? TetSplit::kNone : TetSplit::kSix);
  }
  if (type == "box") {
    spec.expectMap({"generator", "nodes", "size", "split", "length_unit", "scale", "translate", "rotate_deg"});
    const YamlEntry nodes = spec["nodes"];
    if (nodes.size() != 3) nodes.fail("expected 3 node counts [nx, ny, nz]");
    const Eigen::Vector3d size = spec["size"].vector3();
    if ((size.array() <= 0.0).any()) spec["size"].fail("expected positive sizes");
    return boxGrid(nodes[0].integerAtLeast(2), nodes[1].integerAtLeast(2),
                   nodes[2].integerAtLeast(2), size,
                   spec.has("split") ? parseSplit(spec["split"]) : TetSplit::kFiveMirrored);
  }
  if (type == "cantilever") {
    spec.expectMap({"generator", "length", "width", "cells_along", "cells_across", "split",
                    "length_unit", "scale", "translate", "rotate_deg"});
    return cantileverBeam(spec["length"].positive(), spec["width"].positive(),
                          spec.integerAtLeast("cells_along", 1, 10),
                          spec.integerAtLeast("cells_across", 1, 2),
                          spec.has("split") ? parseSplit(spec["split"]) : TetSplit::kSixMirrored);
  }
  spec.expectMap({"generator", "length", "max_radius", "tendon_radius", "segments", "layers",
                  "length_unit", "scale", "translate", "rotate_deg"});
  SpindleShape shape;
  shape.length = spec.positive("length", shape.length);
  shape.maxRadius = spec.positive("max_radius", shape.maxRadius);
  shape.tendonRadius = spec.positive("tendon_radius", shape.tendonRadius);
  if (shape.tendonRadius >= shape.maxRadius)
    spec[spec.has("tendon_radius") ? "tendon_radius" : "max_radius"].fail(
        "expected tendon_radius < max_radius");
  shape.segments = spec.integerAtLeast("segments", 3, shape.segments);
  shape.layers = spec.integerAtLeast("layers", 2, shape.layers);
  return spindleMuscle(shape);
}

// Where the mesh's file coordinates go: x_world = R (scale x) + t, with
// R = Rz(rz) Ry(ry) Rx(rx) from mesh.rotate_deg (degrees, about the world axes, x first) and
// t = mesh.translate (m), both applied after length_unit and scale.
struct Placement {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  void apply(Eigen::Matrix3Xd& points) const {
    points = (rotation * (scale * points)).colwise() + translation;
  }
};

Placement readPlacement(const YamlEntry& spec) {
  Placement p;
  if (spec.has("length_unit")) p.scale = lengthUnit(spec["length_unit"]);
  if (spec.has("scale")) p.scale *= spec["scale"].positive();
  if (spec.has("translate")) p.translation = spec["translate"].vector3();
  if (spec.has("rotate_deg")) {
    const Eigen::Vector3d deg = spec["rotate_deg"].vector3();
    const Eigen::Vector3d rad = deg * (M_PI / 180.0);
    p.rotation = (Eigen::AngleAxisd(rad.z(), Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(rad.y(), Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(rad.x(), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
  }
  return p;
}

std::string describeTet(const Mesh& mesh, int t) {
  const Tet& tet = mesh.tets[t];
  char buf[160];
  std::snprintf(buf, sizeof buf, "tet %d (nodes %d %d %d %d, normalised volume %.3g)", t, tet[0],
                tet[1], tet[2], tet[3], tetNormalisedVolume(mesh.rest, tet));
  return buf;
}

// A flat tet fails the scene, or is dropped with a note when mesh.drop_degenerate says so.
void handleFlatTets(const YamlEntry& spec, Mesh& mesh, std::vector<std::string>& notes) {
  const std::vector<int> flat = flatTets(mesh);
  if (flat.empty()) return;
  char limit[32];
  std::snprintf(limit, sizeof limit, "%g", kFlatTetVolume);
  const std::string what = std::to_string(flat.size()) + " flat tet(s) (normalised volume below " +
                           limit + "), the first " + describeTet(mesh, flat.front());
  if (!spec.boolean("drop_degenerate", false))
    spec.fail("a mesh without flat tets: " + what +
              "; remesh it (TetGen -q) or set drop_degenerate: true");
  const std::vector<int> unusedBefore = unusedNodes(mesh);
  removeTets(mesh, flat);
  std::vector<int> orphans;
  const std::vector<int> unusedAfter = unusedNodes(mesh);
  std::set_difference(unusedAfter.begin(), unusedAfter.end(), unusedBefore.begin(),
                      unusedBefore.end(), std::back_inserter(orphans));
  if (!orphans.empty())
    spec.fail("flat tets that can be dropped: " + what + "; without them node " +
              std::to_string(orphans.front()) + " belongs to no element");
  notes.push_back("dropped " + what);
}

// mesh.node_order of a mesh file: rcm (default), morton or file (mesh_order.h). Scene keys,
// files beside the mesh and messages keep the file's numbers (docs/scene_format.md).
NodeOrdering readNodeOrdering(const YamlEntry& spec) {
  if (!spec.has("node_order")) return NodeOrdering::kReverseCuthillMcKee;
  const std::string order = spec["node_order"].choice({"rcm", "morton", "file"});
  if (order == "file") return NodeOrdering::kFile;
  return order == "morton" ? NodeOrdering::kMorton : NodeOrdering::kReverseCuthillMcKee;
}

Mesh loadMesh(const YamlEntry& spec, const fs::path& sceneDir, std::vector<std::string>& notes,
              Placement& placement, std::optional<EllipsoidShape>& ellipsoid) {
  Mesh mesh;
  if (spec.has("file")) {
    spec.expectMap({"file", "length_unit", "scale", "translate", "rotate_deg", "drop_degenerate",
                    "node_order"});
    const YamlEntry fileEntry = spec["file"];
    fs::path file = fileEntry.text();
    if (file.is_relative()) file = sceneDir / file;
    if (!fs::is_regular_file(file)) fileEntry.fail("mesh file '" + file.string() + "' not found");
    ReadNotes readNotes;
    mesh = readMesh(file.string(), &readNotes);
    for (auto& line : readNotes.lines) notes.push_back(file.filename().string() + ": " + line);
  } else if (spec.has("generator")) {
    mesh = generateMesh(spec, ellipsoid);
  } else {
    spec.fail("expected 'file' or 'generator'");
  }
  placement = readPlacement(spec);
  placement.apply(mesh.rest);
  // A rotation turns the fibre frames with the mesh (orientation and volumes are kept).
  for (Eigen::Matrix3d& frame : mesh.fibreFrame) frame = placement.rotation * frame;
  for (Eigen::Matrix3d& frame : mesh.hexFibreFrame) frame = placement.rotation * frame;
  if (mesh.numTets() == 0 && mesh.numHexes() == 0)
    spec.fail("the mesh has no tetrahedra or hexahedra");
  handleFlatTets(spec, mesh, notes);
  const NodeOrdering ordering =
      spec.has("file") ? readNodeOrdering(spec) : NodeOrdering::kFile;
  if (ordering != NodeOrdering::kFile) applyOrder(mesh, localityOrder(mesh, ordering));
  return mesh;
}

// render_surface: {file: OBJ, outside: clamp | extrapolate}; the OBJ is in the mesh file's
// coordinates and gets the mesh's placement.
RenderSurface loadRenderSurface(const YamlEntry& spec, const fs::path& sceneDir,
                                const Placement& placement, const Mesh& mesh,
                                std::vector<std::string>& notes) {
  spec.expectMap({"file", "outside"});
  OutsidePolicy policy = OutsidePolicy::kExtrapolate;
  if (spec.has("outside") && spec["outside"].choice({"clamp", "extrapolate"}) == "clamp")
    policy = OutsidePolicy::kClamp;
  const YamlEntry fileEntry = spec["file"];
  fs::path file = fileEntry.text();
  if (file.is_relative()) file = sceneDir / file;
  if (!fs::is_regular_file(file)) fileEntry.fail("surface file '" + file.string() + "' not found");
  SurfaceMesh surface = readObj(file.string());
  if (surface.triangles.empty()) fileEntry.fail("the surface has no triangles");
  placement.apply(surface.vertices);
  RenderSurface render;
  render.file = file.string();
  render.rest = surface.vertices;
  render.triangles = std::move(surface.triangles);
  render.embedding = Embedding(mesh, render.rest, policy);
  notes.push_back("render surface " + file.filename().string() + ": " +
                  std::to_string(render.embedding.numPoints()) + " vertices, " +
                  std::to_string(render.embedding.numOutside()) + " outside the mesh (up to " +
                  std::to_string(render.embedding.maxOutsideDistance()) + " m)");
  return render;
}

// contact: {stiffness | stiffness_per_area, sample_spacing, damping, grasp_stiffness, grasp_jaw_angle,
// grasp_radius, grasp_max_nodes, felt_stiffness, tool_max_speed}; every key optional (defaults in
// ContactSettings).
ContactSettings readContact(const YamlEntry& spec) {
  if (spec.node().IsNull()) return {};
  spec.expectMap({"stiffness", "stiffness_per_area", "sample_spacing", "damping", "grasp_stiffness",
                  "grasp_jaw_angle", "grasp_radius", "grasp_max_nodes", "felt_stiffness",
                  "tool_max_speed"});
  ContactSettings c;
  if (spec.has("stiffness") && spec.has("stiffness_per_area"))
    spec["stiffness_per_area"].fail(
        "give either stiffness (N/m per contact point) or stiffness_per_area (N/m^3, the contact "
        "per unit area), not both");
  c.stiffness = spec.positive("stiffness", c.stiffness);
  c.stiffnessPerArea = spec.positive("stiffness_per_area", c.stiffnessPerArea);
  if (spec.has("sample_spacing") && !spec.has("stiffness_per_area"))
    spec["sample_spacing"].fail("is for the contact per unit area: give stiffness_per_area too");
  c.sampleSpacing = spec.positive("sample_spacing", c.sampleSpacing);
  if (spec.has("damping")) {
    c.damping = spec["damping"].number();
    if (c.damping < 0.0) spec["damping"].fail("expected a non-negative damping (N s/m)");
  }
  c.graspStiffness = spec.positive("grasp_stiffness", c.graspStiffness);
  if (spec.has("grasp_jaw_angle")) {
    c.graspJawAngle = spec["grasp_jaw_angle"].number();
    if (c.graspJawAngle < 0.0 || c.graspJawAngle > M_PI)
      spec["grasp_jaw_angle"].fail("expected an angle in [0, pi] (rad)");
  }
  c.graspRadius = spec.positive("grasp_radius", c.graspRadius);
  c.graspMaxNodes = spec.integerAtLeast("grasp_max_nodes", 1, c.graspMaxNodes);
  if (spec.has("tool_max_speed")) {
    const YamlEntry e = spec["tool_max_speed"];
    c.toolMaxSpeed = e.number();
    if (c.toolMaxSpeed <= 0.0) e.fail("expected a speed > 0 (m/s), got " + e.node().Scalar());
  }
  if (spec.has("felt_stiffness"))
    c.tissueInSeries = spec["felt_stiffness"].choice({"penalty", "tissue_in_series"}) ==
                       "tissue_in_series";
  return c;
}

// An optional number key, or the fallback; `valid` is the accepted range, `expected` says it.
template <class Valid>
double checkedNumber(const YamlEntry& spec, const char* key, double fallback, Valid valid,
                     const char* expected) {
  if (!spec.has(key)) return fallback;
  const YamlEntry e = spec[key];
  const double value = e.number();
  if (!valid(value)) e.fail(std::string(expected) + ", got '" + e.node().Scalar() + "'");
  return value;
}

// stability_guard: {enabled, max_halvings, energy_growth, energy_slack, min_volume_ratio};
// every key optional (defaults in StabilityGuardParams). Returns false when disabled.
bool readStabilityGuard(const YamlEntry& spec, StabilityGuardParams& p) {
  if (spec.node().IsNull()) return true;
  spec.expectMap({"enabled", "max_halvings", "energy_growth", "energy_slack", "min_volume_ratio"});
  p.maxHalvings = static_cast<int>(checkedNumber(
      spec, "max_halvings", p.maxHalvings,
      [](double v) { return v >= 0 && v <= 16 && v == std::floor(v); },
      "expected an integer in [0, 16]"));
  p.energyGrowth = checkedNumber(spec, "energy_growth", p.energyGrowth,
                                 [](double v) { return v > 1.0; }, "expected a number > 1");
  p.energySlack = checkedNumber(spec, "energy_slack", p.energySlack,
                                [](double v) { return v >= 0.0; },
                                "expected a non-negative energy (J)");
  p.minVolumeRatio = checkedNumber(spec, "min_volume_ratio", p.minVolumeRatio,
                                   [](double v) { return v >= 0.0 && v < 1.0; },
                                   "expected a volume ratio in [0, 1)");
  return spec.boolean("enabled", true);
}

std::uint8_t parseAxes(const YamlEntry& e) {
  const std::string axes = e.text();
  std::uint8_t bits = 0;
  for (char c : axes) {
    if (c == 'x') bits |= kFixedX;
    else if (c == 'y') bits |= kFixedY;
    else if (c == 'z') bits |= kFixedZ;
    else e.fail("expected a combination of x, y and z (e.g. 'xyz' or 'z')");
  }
  if (bits == 0) e.fail("expected at least one axis");
  return bits;
}

// The keys of a `materials` entry: the common ones, the Lame constants (read by the laws and
// models that use them) and every registered law's own keys.
std::vector<std::string> materialKeys() {
  std::vector<std::string> keys{"name", "region", "fibres", "density", "stress_unit"};
  for (const std::string& key : elasticConstantKeys()) keys.push_back(key);
  for (const LawEntry& law : registry().laws())
    for (const KeyDoc& k : law.materialKeys)
      if (std::find(keys.begin(), keys.end(), k.key) == keys.end()) keys.push_back(k.key);
  return keys;
}

// A law's key in a `materials` entry when no force model of the scene uses that law would be
// read by nothing: an error at the key, not a silent no-op.
void rejectUnusedLawKeys(const YamlEntry& materialList, const YamlEntry& models) {
  std::vector<std::string> used;
  for (size_t k = 0; k < models.size(); ++k)
    if (models[k].has("law")) used.push_back(models[k]["law"].text());
  const auto readByUsedLaw = [&](const std::string& key) {
    for (const std::string& name : used)
      if (const LawEntry* law = registry().findLaw(name))
        for (const KeyDoc& k : law->materialKeys)
          if (k.key == key) return true;
    return false;
  };
  for (size_t m = 0; m < materialList.size(); ++m)
    for (const LawEntry& law : registry().laws())
      for (const KeyDoc& k : law.materialKeys)
        if (materialList[m].has(k.key.c_str()) && !readByUsedLaw(k.key))
          materialList[m][k.key.c_str()].fail("read by the law '" + law.name +
                                              "', which no force model of this scene uses");
}

// The Lame constants the force models read go into System::materials; an entry that gives them
// when no model reads them gets one note naming the keys (earlier scenes had to state them).
void keepElasticConstants(const YamlEntry& materialList, const ModelContext& context,
                          System& system, std::vector<std::string>& notes) {
  for (size_t m = 0; m < materialList.size(); ++m) {
    if (m < context.elasticRead.size() && context.elasticRead[m]) {
      system.materials[m].elastic = context.elasticRead[m];
      continue;
    }
    std::string given;
    for (const std::string& key : elasticConstantKeys())
      if (materialList[m].has(key.c_str())) given += (given.empty() ? "" : ", ") + key;
    if (!given.empty())
      notes.push_back(materialList[m].path() + " (line " +
                      std::to_string(materialList[m].node().Mark().line + 1) + "): " + given +
                      " read by no force model of this scene (only stvk, neo_hookean, "
                      "tensor_mass, edge_length and stvk_displacement read them); remove them");
  }
}

// What every material has; the constants of its law are read by the law (ModelContext).
Material parseMaterial(const YamlEntry& spec) {
  spec.expectMap(materialKeys());
  if (spec.has("stress_unit")) stressUnit(spec["stress_unit"]);  // checked even when unread
  Material m;
  m.density = spec.positive("density", m.density);
  return m;
}

std::vector<Material> assignMaterials(const YamlEntry& list, Mesh& mesh) {
  std::vector<Material> materials;
  std::vector<int> assigned(mesh.numTets() + mesh.numHexes(), -1);
  if (list.size() == 0) list.fail("expected at least one material");
  for (size_t k = 0; k < list.size(); ++k) {
    const YamlEntry spec = list[k];
    materials.push_back(parseMaterial(spec));
    if (!spec.has("region")) {
      std::fill(assigned.begin(), assigned.end(), static_cast<int>(k));
      continue;
    }
    for (int e : regionElements(spec["region"], mesh)) assigned[e] = static_cast<int>(k);
  }
  int unassigned = 0;
  for (int id : assigned) unassigned += id < 0;
  if (unassigned > 0)
    list.fail(std::to_string(unassigned) + " elements are in no material's region");
  mesh.material.assign(assigned.begin(), assigned.begin() + mesh.numTets());
  mesh.hexMaterial.assign(assigned.begin() + mesh.numTets(), assigned.end());
  return materials;
}

// A motion that has a component along an axis it does not control would be ignored there.
void checkControlledAxes(const YamlEntry& e, const Eigen::Vector3d& motion, std::uint8_t axes) {
  for (int axis = 0; axis < 3; ++axis)
    if (!(axes & (1u << axis)) && motion[axis] != 0.0)
      e.fail(std::string("expected no motion along ") + "xyz"[axis] +
             ", which the entry does not control (see axes)");
}

// The prescribed motion of controlled axes ("Adamss: Advanced Anisotropic Mass-Spring System",
// Sec. 2.6): one of path [[t, dx, dy, dz], ...], velocity [vx, vy, vz] (m/s, from t = 0) or
// step [dx, dy, dz] (m per frame of run.frame_time, the thesis's predefined step per step).
PrescribedPath readPrescription(const YamlEntry& item, std::uint8_t axes, double frameTime) {
  const int given = item.has("path") + item.has("velocity") + item.has("step");
  if (given != 1)
    item.fail(given == 0 ? "expected one of 'path', 'velocity' or 'step' for the controlled axes"
                         : "expected only one of 'path', 'velocity' or 'step'");
  PrescribedPath p;
  if (item.has("velocity") || item.has("step")) {
    const YamlEntry e = item[item.has("velocity") ? "velocity" : "step"];
    p.velocity = e.vector3() / (item.has("step") ? frameTime : 1.0);
    checkControlledAxes(e, p.velocity, axes);
    return p;
  }
  const YamlEntry path = item["path"];
  if (path.size() == 0) path.fail("expected at least one [t, dx, dy, dz] key");
  for (size_t i = 0; i < path.size(); ++i) {
    const YamlEntry key = path[i];
    if (key.size() != 4) key.fail("expected [t, dx, dy, dz]");
    const double t = key[0].number();
    if (!p.times.empty() && t <= p.times.back()) key[0].fail("expected times in increasing order");
    p.times.push_back(t);
    p.offsets.emplace_back(key[1].number(), key[2].number(), key[3].number());
    checkControlledAxes(key, p.offsets.back(), axes);
  }
  return p;
}

// tags: {file, path | velocity | step}: the fixation and control tags of an index file
// (readNodeTagFile); its controlled nodes follow the entry's motion, one set per axis mask.
void applyTagFile(const YamlEntry& spec, const fs::path& sceneDir, double frameTime,
                  System& system) {
  spec.expectMap({"file", "path", "velocity", "step"});
  const YamlEntry fileEntry = spec["file"];
  fs::path file = fileEntry.text();
  if (file.is_relative()) file = sceneDir / file;
  if (!fs::is_regular_file(file)) fileEntry.fail("tag file '" + file.string() + "' not found");
  const std::vector<NodeTagLine> lines = readNodeTagFile(file.string(), system.numNodes());
  std::vector<int> byAxes[8];
  for (const NodeTagLine& tag : lines) {
    const int node = system.mesh.numbering.nodeFromFile(tag.node);
    system.mesh.nodeTags[node] |= tag.fixed;
    if (tag.controlled) byAxes[tag.controlled].push_back(node);
  }
  const bool controls = std::any_of(lines.begin(), lines.end(),
                                    [](const NodeTagLine& t) { return t.controlled != 0; });
  const bool moves = spec.has("path") || spec.has("velocity") || spec.has("step");
  if (!controls) {
    if (moves)
      spec.fail("the tag file controls no node (X, Y, Z), so nothing reads the motion");
    return;
  }
  // A motion along an axis that no line controls would be dropped: refuse it instead.
  std::uint8_t anyControlled = 0;
  for (const NodeTagLine& tag : lines) anyControlled |= tag.controlled;
  const PrescribedPath path = readPrescription(spec, anyControlled, frameTime);
  for (std::uint8_t axes = 1; axes < 8; ++axes) {
    if (byAxes[axes].empty()) continue;
    ControlledSet set;
    set.nodes = byAxes[axes];
    set.axes = axes;
    set.path = path;
    system.controlled.push_back(std::move(set));
  }
}

// jawNodes gets the nodes of the fixed entries marked `jaw: true`, which a landmark fit's jaw
// transform moves (docs/muscles.md, "Landmark fitting"); sorted, each once.
void applyBoundary(const YamlEntry& spec, const fs::path& sceneDir, double frameTime,
                   System& system, std::vector<int>& jawNodes) {
  spec.expectMap({"fixed", "controlled", "tags"});
  if (spec.has("fixed")) {
    const YamlEntry list = spec["fixed"];
    for (size_t k = 0; k < list.size(); ++k) {
      const YamlEntry item = list[k];
      item.expectMap({"box", "plane", "nodes", "axes", "jaw"});
      const std::uint8_t axes = item.has("axes") ? parseAxes(item["axes"]) : std::uint8_t{kFixedAll};
      const bool jaw = item.boolean("jaw", false);
      if (jaw && axes != kFixedAll)
        item["axes"].fail("expected xyz for a jaw entry: the jaw moves its nodes on all axes");
      for (int n : selectNodes(item, system.mesh)) {
        system.mesh.nodeTags[n] |= axes;
        if (jaw) jawNodes.push_back(n);
      }
    }
  }
  std::sort(jawNodes.begin(), jawNodes.end());
  jawNodes.erase(std::unique(jawNodes.begin(), jawNodes.end()), jawNodes.end());
  if (spec.has("controlled")) {
    const YamlEntry list = spec["controlled"];
    for (size_t k = 0; k < list.size(); ++k) {
      const YamlEntry item = list[k];
      item.expectMap({"box", "plane", "nodes", "axes", "path", "velocity", "step"});
      ControlledSet set;
      set.nodes = selectNodes(item, system.mesh);
      if (item.has("axes")) set.axes = parseAxes(item["axes"]);
      set.path = readPrescription(item, set.axes, frameTime);
      system.controlled.push_back(std::move(set));
    }
  }
  if (spec.has("tags")) applyTagFile(spec["tags"], sceneDir, frameTime, system);
  system.updateConstraints();
}

void applyLoads(const YamlEntry& spec, System& system) {
  spec.expectMap(
      {"gravity", "rayleigh_mass", "node_damping", "initial_velocity", "initial_displacement"});
  if (spec.has("gravity"))
    system.models.push_back(std::make_unique<GravityModel>(system.mass, spec["gravity"].vector3()));
  if (spec.has("rayleigh_mass")) {
    const YamlEntry e = spec["rayleigh_mass"];
    const double alpha = e.number();
    if (alpha < 0.0) e.fail("expected a non-negative mass-proportional damping (1/s)");
    system.damping += alpha * system.mass;
  }
  if (spec.has("node_damping")) {
    const YamlEntry e = spec["node_damping"];
    const double gamma = e.number();
    if (gamma < 0.0) e.fail("expected a non-negative damping per node (N s/m)");
    system.damping.array() += gamma;
  }
  // "Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.4.4.4: every particle starts
  // with v0 (the boundary's prescription then sets the constrained DOFs' own velocities).
  if (spec.has("initial_velocity")) {
    const Eigen::Vector3d v0 = spec["initial_velocity"].vector3();
    for (int n = 0; n < system.numNodes(); ++n) system.state.v.segment<3>(3 * n) = v0;
  }
  // Ibid., Sec. 2.5.1, Eq. 2.124: the state at t = 0 differs from the initialised (rest) one by
  // an initial displacement, u_init = u^0 + Delta u. The key gives d = u^0 - u_init = -Delta u,
  // the displacement of every particle from rest (the boundary's prescription then puts the
  // constrained DOFs back where it holds them); the forces keep the rest state as reference.
  if (spec.has("initial_displacement")) {
    const Eigen::Vector3d d = spec["initial_displacement"].vector3();
    for (int n = 0; n < system.numNodes(); ++n)
      system.state.x.segment<3>(3 * n) = system.mesh.rest.col(n) + d;
  }
}

std::optional<KineticEnergyStop> readKineticEnergyStop(const YamlEntry& run) {
  if (!run.has("stop_kinetic_energy")) {
    if (run.has("stop_not_before"))
      run["stop_not_before"].fail("applies only together with stop_kinetic_energy");
    return std::nullopt;
  }
  KineticEnergyStop stop;
  stop.below = run["stop_kinetic_energy"].positive();
  if (run.has("stop_not_before")) {
    const YamlEntry e = run["stop_not_before"];
    stop.notBefore = e.number();
    if (!(stop.notBefore >= 0.0)) e.fail("expected a time >= 0 (s)");
  }
  return stop;
}

}  // namespace

Scene loadScene(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "scene file");
  Scene scene;
  scene.file = path;
  const YamlEntry top(root, "", &scene.file);
  top.expectMap({"name", "mesh", "materials", "fibres", "force_models", "integrator",
                 "boundary", "loads", "run", "output", "contact", "render_surface",
                 "stability_guard"});
  scene.name = top.has("name") ? top["name"].text() : fs::path(path).stem().string();

  const fs::path sceneDir = fs::path(path).parent_path();
  Placement placement;
  FibreGeometry geometry;
  Mesh mesh = loadMesh(top["mesh"], sceneDir, scene.notes, placement, geometry.ellipsoid);
  geometry.scale = placement.scale;
  geometry.rotation = placement.rotation;
  geometry.translation = placement.translation;
  if (top.has("fibres")) applySceneFibres(top["fibres"], sceneDir, geometry, mesh);
  std::vector<Material> materials = assignMaterials(top["materials"], mesh);
  applyMaterialFibres(top["materials"], geometry, mesh);
  scene.system = System(std::move(mesh), std::move(materials));
  System& system = scene.system;

  const YamlEntry models = top["force_models"];
  if (models.size() == 0) models.fail("expected at least one force model");
  ModelContext context{system.mesh, system.materials, {}};
  const YamlEntry materialList = top["materials"];
  for (size_t k = 0; k < materialList.size(); ++k) context.materialEntries.push_back(materialList[k]);
  for (size_t k = 0; k < models.size(); ++k)
    system.models.push_back(registry().makeForceModel(models[k], context));
  rejectUnusedLawKeys(materialList, models);
  keepElasticConstants(materialList, context, system, scene.notes);
  for (const auto& model : system.models)
    if (!model->couplings().empty()) {
      system.addCouplingsToPattern();
      break;
    }
  if (top.has("loads")) applyLoads(top["loads"], system);
  if (top.has("run")) {
    const YamlEntry run = top["run"];
    run.expectMap({"frame_time", "duration", "stop_kinetic_energy", "stop_not_before",
                   "max_frame_time", "settle_time"});
    scene.frameTime = run.positive("frame_time", scene.frameTime);
    scene.duration = run.positive("duration", scene.duration);
    scene.kineticEnergyStop = readKineticEnergyStop(run);
    if (run.has("max_frame_time")) {
      const YamlEntry e = run["max_frame_time"];
      const double longest = e.number();
      if (longest < scene.frameTime) {
        char text[96];
        std::snprintf(text, sizeof text, "expected a time >= run.frame_time (%g s), got %g", scene.frameTime,
                      longest);
        e.fail(text);
      }
      scene.maxFrameTime = longest;
    }
    if (run.has("settle_time")) {
      const YamlEntry e = run["settle_time"];
      scene.settleTime = e.number();
      if (!(scene.settleTime >= 0.0 && std::isfinite(scene.settleTime)))
        e.fail("expected a simulated time >= 0 (s)");
    }
  }
  if (top.has("boundary"))
    applyBoundary(top["boundary"], sceneDir, scene.frameTime, system, scene.jawNodes);
  system.prescribe(0.0, system.state.x, system.state.v);

  const YamlEntry integrator = top["integrator"];
  scene.integrator = registry().makeIntegrator(integrator, scene.notes);
  if (scene.integrator->needsStiffness() && !system.hasStiffness()) {
    std::string missing;
    for (const auto& m : system.models)
      if (!m->hasStiffness()) missing += std::string(missing.empty() ? "" : ", ") + m->name();
    integrator["type"].fail(std::string(scene.integrator->name()) +
                            " needs the stiffness of every force model; " + missing +
                            " provides none");
  }
  StabilityGuardParams guard;
  if (!top.has("stability_guard") || readStabilityGuard(top["stability_guard"], guard))
    scene.integrator = std::make_unique<StabilityGuard>(std::move(scene.integrator), guard);

  if (top.has("output")) {
    const YamlEntry out = top["output"];
    out.expectMap({"vtu_every", "csv"});
    scene.output.vtuEvery = out.integerAtLeast("vtu_every", 0, 0);
    scene.output.csv = out.boolean("csv", false);
  }
  if (top.has("contact")) scene.contact = readContact(top["contact"]);
  if (top.has("render_surface"))
    scene.renderSurface = loadRenderSurface(top["render_surface"], sceneDir, placement,
                                            system.mesh, scene.notes);
  return scene;
}

}  // namespace tt
