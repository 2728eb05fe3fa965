#include "scene_fibres.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "tissue_trainer/core/mesh/fibre_field.h"
#include "tissue_trainer/core/registry/selection.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

int numElements(const Mesh& mesh) { return mesh.numTets() + mesh.numHexes(); }

Eigen::Matrix3d& frameOf(Mesh& mesh, int e) {
  return e < mesh.numTets() ? mesh.fibreFrame[e] : mesh.hexFibreFrame[e - mesh.numTets()];
}

template <class Visit>
void forEachNode(const Mesh& mesh, int e, Visit visit) {
  if (e < mesh.numTets()) {
    for (int a : mesh.tets[e]) visit(a);
  } else {
    for (int a : mesh.hexes[e - mesh.numTets()]) visit(a);
  }
}

Eigen::Vector3d centroid(const Mesh& mesh, int e) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  int count = 0;
  forEachNode(mesh, e, [&](int a) {
    c += mesh.rest.col(a);
    ++count;
  });
  return c / count;
}

// {direction: a0}, {direction: a0, sheet: s0} or {angles_deg: [phi, theta]}.
Eigen::Matrix3d globalFrame(const YamlEntry& spec) {
  if (spec.has("angles_deg")) {
    if (spec.has("direction") || spec.has("sheet"))
      spec["angles_deg"].fail("expected either angles_deg or direction (and sheet), not both");
    const YamlEntry angles = spec["angles_deg"];
    if (angles.size() != 2) angles.fail("expected a list of 2 angles [phi, theta] in degrees");
    return fibreFrameFromAngles(angles[0].number(), angles[1].number());
  }
  Eigen::Vector3d a0 = spec["direction"].vector3();
  if (a0.norm() == 0.0) spec["direction"].fail("expected a non-zero direction");
  a0.normalize();
  Eigen::Vector3d a1;
  if (spec.has("sheet")) {
    const YamlEntry sheet = spec["sheet"];
    a1 = sheet.vector3();
    if (a1.norm() == 0.0) sheet.fail("expected a non-zero sheet direction");
    a1.normalize();
    const double cosine = a1.dot(a0);
    if (std::abs(cosine) > 1e-6)
      sheet.fail("expected a sheet direction orthogonal to the fibre direction, got cosine " +
                 std::to_string(cosine));
  } else {
    const Eigen::Vector3d helper =
        std::abs(a0.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    a1 = a0.cross(helper).normalized();
  }
  Eigen::Matrix3d frame;
  frame << a0, a1, a0.cross(a1);
  return frame;
}

// transmural: {normal, direction, angles_deg: [from, to], extent: [from, to]}; without
// `extent`, the wall spans the elements' nodes along the normal.
TransmuralFibres readTransmural(const YamlEntry& spec, const Mesh& mesh,
                                const std::vector<int>& elements) {
  spec.expectMap({"normal", "direction", "angles_deg", "extent"});
  TransmuralFibres t;
  const Eigen::Vector3d normal = spec["normal"].vector3();
  if (!(normal.norm() > 0.0)) spec["normal"].fail("expected a non-zero wall normal");
  t.normal = normal.normalized();
  const Eigen::Vector3d direction = spec["direction"].vector3();
  const Eigen::Vector3d inPlane = direction - direction.dot(t.normal) * t.normal;
  if (!(inPlane.norm() > 1e-6 * direction.norm()))
    spec["direction"].fail("expected a non-zero fibre direction not parallel to the normal");
  t.reference = inPlane.normalized();
  const YamlEntry angles = spec["angles_deg"];
  if (angles.size() != 2)
    angles.fail("expected a list of 2 angles [at the first face, at the second face] in degrees");
  t.angleFrom = angles[0].number() * M_PI / 180.0;
  t.angleTo = angles[1].number() * M_PI / 180.0;
  if (spec.has("extent")) {
    const YamlEntry extent = spec["extent"];
    if (extent.size() != 2) extent.fail("expected a list of 2 wall positions [from, to] (m)");
    t.from = extent[0].number();
    t.to = extent[1].number();
    if (!(t.from < t.to)) extent.fail("expected from < to");
    return t;
  }
  t.from = std::numeric_limits<double>::infinity();
  t.to = -t.from;
  for (int e : elements)
    forEachNode(mesh, e, [&](int a) {
      const double s = t.normal.dot(mesh.rest.col(a));
      t.from = std::min(t.from, s);
      t.to = std::max(t.to, s);
    });
  if (!(t.from < t.to)) spec["normal"].fail("the elements have no extent along the normal");
  return t;
}

// ellipsoid: {angles_deg: [endocardium, epicardium]}, on the mesh of a truncated_ellipsoid
// generator (its shape in `geometry`).
EllipsoidFibres readEllipsoidFibres(const YamlEntry& spec, const FibreGeometry& geometry) {
  spec.expectMap({"angles_deg"});
  if (!geometry.ellipsoid)
    spec.fail("expected a mesh of generator truncated_ellipsoid: the form takes the wall from "
              "its shape");
  EllipsoidFibres fibres;
  fibres.shape = *geometry.ellipsoid;
  const YamlEntry angles = spec["angles_deg"];
  if (angles.size() != 2)
    angles.fail("expected a list of 2 angles [at the endocardium, at the epicardium] in degrees");
  fibres.angleEndo = angles[0].number() * M_PI / 180.0;
  fibres.angleEpi = angles[1].number() * M_PI / 180.0;
  return fibres;
}

// One `fibres` entry applied to `elements`; a fibre file only at the top level (sceneDir set),
// the ellipsoid form only at the top level and in materials (geometry set).
void applyEntry(const YamlEntry& spec, const std::vector<int>& elements, Mesh& mesh,
                const fs::path* sceneDir, const FibreGeometry* geometry) {
  std::vector<std::string> keys{"direction", "sheet", "angles_deg"};
  if (sceneDir) keys.push_back("file");
  keys.push_back("transmural");
  if (geometry) keys.push_back("ellipsoid");
  spec.expectMap(keys);
  const bool global = spec.has("direction") || spec.has("sheet") || spec.has("angles_deg");
  std::vector<const char*> special;
  for (const char* form : {"file", "transmural", "ellipsoid"})
    if (spec.has(form)) special.push_back(form);
  if (!special.empty() && (global || special.size() > 1))
    spec[special.back()].fail(
        std::string("expected one form of fibres: direction (and sheet), angles_deg, ") +
        (sceneDir ? "file, " : "") + (geometry ? "transmural or ellipsoid" : "or transmural") +
        ", not several");
  if (spec.has("ellipsoid")) {
    const EllipsoidFibres fibres = readEllipsoidFibres(spec["ellipsoid"], *geometry);
    for (int e : elements) {
      const Eigen::Vector3d own =
          geometry->rotation.transpose() * (centroid(mesh, e) - geometry->translation) /
          geometry->scale;
      frameOf(mesh, e) = geometry->rotation * fibres.frameAt(own);
    }
    return;
  }
  if (spec.has("transmural")) {
    const TransmuralFibres t = readTransmural(spec["transmural"], mesh, elements);
    for (int e : elements) frameOf(mesh, e) = t.frameAt(centroid(mesh, e));
    return;
  }
  if (spec.has("file")) {
    const YamlEntry fileEntry = spec["file"];
    fs::path file = fileEntry.text();
    if (file.is_relative()) file = *sceneDir / file;
    if (!fs::is_regular_file(file)) fileEntry.fail("fibre file '" + file.string() + "' not found");
    const std::vector<Eigen::Matrix3d> frames = readFibreFile(file.string(), numElements(mesh));
    for (int e : elements) frameOf(mesh, e) = geometry->rotation * frames[elementToFile(mesh, e)];
    return;
  }
  const Eigen::Matrix3d frame = globalFrame(spec);
  for (int e : elements) frameOf(mesh, e) = frame;
}

}  // namespace

void applySceneFibres(const YamlEntry& spec, const fs::path& sceneDir,
                      const FibreGeometry& geometry, Mesh& mesh) {
  mesh.fillDefaults();
  std::vector<int> all(numElements(mesh));
  for (int e = 0; e < numElements(mesh); ++e) all[e] = e;
  applyEntry(spec, all, mesh, &sceneDir, &geometry);
}

void applyFibres(const YamlEntry& spec, const std::vector<int>& elements, Mesh& mesh) {
  mesh.fillDefaults();
  applyEntry(spec, elements, mesh, nullptr, nullptr);
}

void applyMaterialFibres(const YamlEntry& materialList, const FibreGeometry& geometry,
                         Mesh& mesh) {
  mesh.fillDefaults();
  for (size_t k = 0; k < materialList.size(); ++k) {
    if (!materialList[k].has("fibres")) continue;
    std::vector<int> elements;
    for (int e = 0; e < numElements(mesh); ++e) {
      const int id = e < mesh.numTets() ? mesh.material[e] : mesh.hexMaterial[e - mesh.numTets()];
      if (id == static_cast<int>(k)) elements.push_back(e);
    }
    if (elements.empty())
      materialList[k]["fibres"].fail(
          "no element has this material (later entries override earlier ones in their region)");
    applyEntry(materialList[k]["fibres"], elements, mesh, nullptr, &geometry);
  }
}

}  // namespace tt
