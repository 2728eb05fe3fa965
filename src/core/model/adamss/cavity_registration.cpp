// Registers adamss_cavity (model/adamss/cavity.h).
#include <algorithm>
#include <string>

#include "tissue_trainer/core/model/adamss/cavity.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/registry/selection.h"

namespace tt {
namespace {

// `faces`: a list of node-index facets, 3 or 4 nodes each, in the mesh file's numbers (an
// index out of range stays as it is, for the model's own check to name).
std::vector<adamss::CavityFacet> readFaces(const YamlEntry& list, const Mesh& mesh) {
  std::vector<adamss::CavityFacet> facets;
  const std::size_t count = list.size();
  for (std::size_t f = 0; f < count; ++f) {
    const YamlEntry facet = list[static_cast<int>(f)];
    facets.push_back(facet.integers());
    if (facets.back().size() != 3 && facets.back().size() != 4)
      facet.fail("expected a facet of 3 or 4 node indices");
    for (int& node : facets.back())
      if (node >= 0 && node < mesh.numNodes()) node = mesh.numbering.nodeFromFile(node);
  }
  return facets;
}

// `surface`: the mesh's boundary triangles whose three nodes are all selected.
std::vector<adamss::CavityFacet> readSurface(const YamlEntry& spec, const Mesh& mesh) {
  spec.expectMap({"box", "plane", "nodes"});
  std::vector<char> selected(mesh.numNodes(), 0);
  for (int node : selectNodes(spec, mesh)) selected[node] = 1;
  std::vector<adamss::CavityFacet> facets;
  for (const Triangle& t : mesh.surface)
    if (selected[t[0]] && selected[t[1]] && selected[t[2]]) facets.push_back({t[0], t[1], t[2]});
  if (facets.empty()) spec.fail("no boundary face of the mesh has all its nodes selected");
  return facets;
}

}  // namespace

void registerCavityModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "adamss_cavity";
  e.description = "a closed cavity surface (Adamss Sec. 2.3) with a pressure on its faces "
                  "(Eq. 2.119) and an optional volume penalty; energy and stiffness";
  e.keys = {
      {"faces", "the facets: a list of node-index lists, 3 (triangle) or 4 (quad) each, "
                "consistently oriented; or use surface"},
      {"surface", "the mesh's boundary triangles with all nodes in a selection {box: {min, max}} "
                  "| {plane: {point, normal, tolerance}} | {nodes: [...]}; or use faces"},
      {"pressure", "p in stress_unit, > 0 pushes the walls out of the cavity (default 0): a "
                   "number, or a time curve map (constant, piecewise_linear, twitch)"},
      {"stress_unit", "the unit of pressure (Pa, kPa, MPa; Pa by default)"},
      {"volume_stiffness", "k >= 0 in J/m^6 of the penalty k/2 (V - V_target)^2 (default 0)"},
      {"target_volume_ratio", "V_target / V_rest > 0 (default 1)"}};
  e.coversHexes = true;
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    if (spec.has("faces") == spec.has("surface"))
      spec.fail("expected exactly one of 'faces' (node-index facets) or 'surface' (a selection "
                "of the mesh's boundary faces)");
    const std::vector<adamss::CavityFacet> facets =
        spec.has("faces") ? readFaces(spec["faces"], context.mesh) : readSurface(spec["surface"], context.mesh);
    adamss::CavityParameters p;
    const double unit = spec.has("stress_unit") ? stressUnit(spec["stress_unit"]) : 1.0;
    if (spec.has("pressure") && spec["pressure"].node().IsMap()) {
      p.pressureFollowsCurve = true;
      p.pressureCurve = readTimeCurve(spec["pressure"], unit);
    } else {
      p.pressure = spec.number("pressure", 0.0) * unit;
    }
    if (spec.has("volume_stiffness")) {
      const YamlEntry k = spec["volume_stiffness"];
      p.volumeStiffness = k.number();
      if (!(p.volumeStiffness >= 0.0))
        k.fail("expected a volume stiffness >= 0, got '" + k.node().Scalar() + "'");
    }
    p.targetVolumeRatio = spec.positive("target_volume_ratio", 1.0);
    if (!p.pressureFollowsCurve && p.pressure == 0.0 && p.volumeStiffness == 0.0)
      spec.fail("expected a non-zero pressure or volume_stiffness (the cavity would do nothing)");
    try {
      return std::make_unique<adamss::CavityModel>(context.mesh.rest, facets, p);
    } catch (const std::invalid_argument& error) {
      (spec.has("faces") ? spec["faces"] : spec["surface"]).fail(error.what());
    }
  };
  registry.add(std::move(e));
}

}  // namespace tt
