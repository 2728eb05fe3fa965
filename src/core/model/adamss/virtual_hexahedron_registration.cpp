// Registers virtual_hexahedron (model/adamss/virtual_hexahedron.h): the method of the virtual
// hexahedron of "Adamss: Advanced Anisotropic Mass-Spring System" (Sec. 2.4.2) over any
// registered law, built by the law's own entry.
#include "tissue_trainer/core/material/volume.h"
#include "tissue_trainer/core/model/law_model_factory.h"

namespace tt {

void registerVirtualHexahedronModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "virtual_hexahedron";
  e.description =
      "Adamss virtual hexahedron: a registered law's forces at the anisotropy axes' "
      "intersection points, carried to the nodes (tets: equal to hyperelastic; hexes: F at "
      "the centre)";
  e.keys = {{"law", "the material law (see the laws listed below), required"},
            {"deformation_gradient",
             "shape_functions (default; exact on tets, the centre of hexes) or "
             "axis_approximation (from axis stretches and angles, Adamss Eqs. 2.59-2.62: "
             "approximate, no stiffness: explicit integrators, or implicit ones with "
             "finite-difference Jacobians)"},
            {"distribution",
             "law volume only: axes (default; the point forces to the nodes by the "
             "intersection points' weights, Eq. 2.29) or vertices (each point force in equal "
             "parts to its face's nodes, Adamss Sec. 2.4.2.3; no energy, and a moment about "
             "the element in general)"}};
  for (KeyDoc& key : lawOptionKeys()) e.keys.push_back(std::move(key));
  e.presets = {
      {"virtual_hexahedron_hunter_polynomial", "{law: hunter_polynomial}",
       "the pole-free Hunter myocardium law through the virtual hexahedron"}};
  e.coversHexes = true;
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    const LawEntry& law = tt::registry().law(spec["law"]);
    LawModelRequest request;
    request.kind = LawModelKind::kVirtualHexahedron;
    request.options = readLawOptions(spec);
    if (spec.has("deformation_gradient") &&
        spec["deformation_gradient"].choice({"shape_functions", "axis_approximation"}) ==
            "axis_approximation")
      request.deformationGradient = adamss::DeformationGradientSource::kAxisApproximation;
    if (spec.has("distribution")) {
      const YamlEntry distribution = spec["distribution"];
      if (spec["law"].text() != VolumeLaw::kName)
        distribution.fail("applies to law: volume only (the volume preservation forces of "
                          "Adamss Sec. 2.4.2.3)");
      if (distribution.choice({"axes", "vertices"}) == "vertices")
        request.distribution = adamss::PointForceDistribution::kVertices;
    }
    if (context.mesh.tets.empty() && context.mesh.hexes.empty())
      spec.fail("the mesh has no tetrahedra or hexahedra");
    try {
      return law.makeModel(context, request);
    } catch (const std::invalid_argument& e) {  // an element or its axes unusable
      spec.fail(e.what());
    }
  };
  registry.add(std::move(e));
}

}  // namespace tt
