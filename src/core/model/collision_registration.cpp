// Registers collision (model/collision.h). Its entry:
//   {type: collision, stiffness: eps (N/m), nodes: surface | all | {box | plane | nodes | region},
//    psd_projection: false,
//    bodies: [{plane: {point, normal}} | {sphere: {centre, radius}} |
//             {mesh: {file: body.obj, scale, translate}}, ...]}
#include <algorithm>
#include <filesystem>
#include <string>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/model/collision.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/registry/selection.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

// The nodes of the elements a region names (as in `materials`), sorted, each once.
std::vector<int> regionNodes(const YamlEntry& region, const Mesh& mesh) {
  std::vector<int> nodes;
  for (int e : regionElements(region, mesh)) {
    if (e < mesh.numTets())
      nodes.insert(nodes.end(), mesh.tets[e].begin(), mesh.tets[e].end());
    else
      nodes.insert(nodes.end(), mesh.hexes[e - mesh.numTets()].begin(),
                   mesh.hexes[e - mesh.numTets()].end());
  }
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

std::vector<int> readNodes(const YamlEntry* spec, const Mesh& mesh) {
  std::vector<int> nodes;
  if (spec && !spec->node().IsScalar()) {
    spec->expectMap({"box", "plane", "nodes", "region"});
    if (spec->node().size() != 1)
      spec->fail("expected one of 'box', 'plane', 'nodes' or 'region'");
    return spec->has("region") ? regionNodes((*spec)["region"], mesh) : selectNodes(*spec, mesh);
  }
  if (spec && spec->choice({"surface", "all"}) == "all") {
    for (int i = 0; i < mesh.numNodes(); ++i) nodes.push_back(i);
    return nodes;
  }
  const std::vector<Triangle> surface = mesh.surface.empty() ? extractSurface(mesh) : mesh.surface;
  for (const Triangle& t : surface) nodes.insert(nodes.end(), t.begin(), t.end());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

// mesh: {file, scale, translate}: a closed OBJ surface, x <- scale x + translate.
ClosedSurface readSurface(const YamlEntry& spec) {
  spec.expectMap({"file", "scale", "translate"});
  const YamlEntry fileEntry = spec["file"];
  fs::path file = fileEntry.text();
  if (file.is_relative()) file = fs::path(spec.file()).parent_path() / file;
  if (!fs::is_regular_file(file)) fileEntry.fail("surface file '" + file.string() + "' not found");
  SurfaceMesh surface = readObj(file.string());
  const double scale = spec.positive("scale", 1.0);
  const Eigen::Vector3d shift = spec.has("translate") ? spec["translate"].vector3() : Eigen::Vector3d::Zero();
  surface.vertices = (scale * surface.vertices).colwise() + shift;
  try {
    return ClosedSurface(std::move(surface.vertices), std::move(surface.triangles));
  } catch (const std::invalid_argument& e) {
    fileEntry.fail(std::string("expected a closed, consistently oriented surface: ") + e.what());
  }
}

CollisionBody readBody(const YamlEntry& item, std::vector<ClosedSurface>& surfaces) {
  item.expectMap({"plane", "sphere", "mesh"});
  if (item.has("plane") + item.has("sphere") + item.has("mesh") != 1)
    item.fail("expected exactly one of 'plane', 'sphere' or 'mesh'");
  if (item.has("plane")) {
    const YamlEntry p = item["plane"];
    p.expectMap({"point", "normal"});
    const Eigen::Vector3d normal = p["normal"].vector3();
    if (!(normal.norm() > 0.0)) p["normal"].fail("expected a non-zero normal (out of the body)");
    return CollisionBody::plane(p["point"].vector3(), normal);
  }
  if (item.has("sphere")) {
    const YamlEntry s = item["sphere"];
    s.expectMap({"centre", "radius"});
    return CollisionBody::sphere(s["centre"].vector3(), s["radius"].positive());
  }
  surfaces.push_back(readSurface(item["mesh"]));
  CollisionBody b;
  b.kind = CollisionBody::Kind::kMesh;
  b.surface = static_cast<int>(surfaces.size()) - 1;
  return b;
}

}  // namespace

void registerCollisionModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "collision";
  e.description = "penalty forces eps d n pushing nodes out of rigid bodies (planes, spheres, "
                  "closed OBJ surfaces), d the depth (\"Derivation of Quasistatics and "
                  "Landmark Optimization for Muscles\", Sec. 5.7)";
  e.keys = {{"stiffness", "required: eps > 0 (N/m): the force is eps times the node's depth"},
            {"bodies",
             "required: a list of {plane: {point, normal (out of the body)}}, {sphere: {centre, "
             "radius}} or {mesh: {file: closed OBJ, scale (1), translate ([0, 0, 0])}}"},
            {"nodes", "the nodes tested: surface (default), all, {box: {min, max}}, {plane: "
                      "{point, normal, tolerance}}, {nodes: [i, ...]} or {region: R} (the nodes "
                      "of the elements of a materials-style region R)"},
            {"psd_projection",
             "true: a sphere's stiffness drops its tangential (curvature) part, so -K is PSD "
             "(default false)"}};
  e.coversHexes = true;
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    const double stiffness = spec["stiffness"].positive();
    const YamlEntry list = spec["bodies"];
    if (list.size() == 0) list.fail("expected at least one body {plane | sphere | mesh}");
    std::vector<CollisionBody> bodies;
    std::vector<ClosedSurface> surfaces;
    for (size_t k = 0; k < list.size(); ++k) bodies.push_back(readBody(list[static_cast<int>(k)], surfaces));
    std::vector<int> nodes;
    if (spec.has("nodes")) {
      const YamlEntry n = spec["nodes"];
      nodes = readNodes(&n, context.mesh);
    } else {
      nodes = readNodes(nullptr, context.mesh);
    }
    if (nodes.empty()) spec.fail("the mesh has no surface nodes; give nodes: all");
    return std::make_unique<CollisionModel>(context.mesh.numNodes(), std::move(nodes), stiffness,
                                            std::move(bodies), std::move(surfaces),
                                            spec.boolean("psd_projection", false));
  };
  registry.add(std::move(e));
}

}  // namespace tt
