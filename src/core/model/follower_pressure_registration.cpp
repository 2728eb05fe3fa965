// Registers follower_pressure (model/follower_pressure.h).
#include <memory>
#include <vector>

#include "tissue_trainer/core/model/follower_pressure.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/registry/selection.h"

namespace tt {
namespace {

// `surface`: the mesh's boundary triangles whose three nodes are all selected (a boundary quad
// of a hex mesh is two of them).
std::vector<FollowerPressureModel::Face> followerPressureFaces(const YamlEntry& spec,
                                                               const Mesh& mesh) {
  spec.expectMap({"box", "plane", "nodes"});
  std::vector<char> selected(mesh.numNodes(), 0);
  for (int node : selectNodes(spec, mesh)) selected[node] = 1;
  std::vector<FollowerPressureModel::Face> faces;
  for (const Triangle& t : mesh.surface)
    if (selected[t[0]] && selected[t[1]] && selected[t[2]]) faces.push_back({t[0], t[1], t[2]});
  if (faces.empty()) spec.fail("no boundary face of the mesh has all its nodes selected");
  return faces;
}

}  // namespace

void registerFollowerPressureModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "follower_pressure";
  e.description = "a pressure on selected boundary faces that follows the deformed surface "
                  "(-p a / 3 per node of each current triangle); symmetrised stiffness, no energy";
  e.keys = {
      {"surface", "the mesh's boundary triangles with all nodes in a selection {box: {min, max}} "
                  "| {plane: {point, normal, tolerance}} | {nodes: [...]}, required"},
      {"pressure", "p in stress_unit, > 0 pushes into the body, required: a number, or a time "
                   "curve map (constant, piecewise_linear, twitch) that ramps it"},
      {"stress_unit", "the unit of pressure (Pa, kPa, MPa; Pa by default)"}};
  e.coversHexes = true;
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    std::vector<FollowerPressureModel::Face> faces =
        followerPressureFaces(spec["surface"], context.mesh);
    const double unit = spec.has("stress_unit") ? stressUnit(spec["stress_unit"]) : 1.0;
    const YamlEntry pressure = spec["pressure"];
    if (pressure.node().IsMap())
      return std::make_unique<FollowerPressureModel>(std::move(faces),
                                                     readTimeCurve(pressure, unit));
    return std::make_unique<FollowerPressureModel>(std::move(faces), pressure.number() * unit);
  };
  registry.add(std::move(e));
}

}  // namespace tt
