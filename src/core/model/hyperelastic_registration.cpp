// Registers hyperelastic (model/hyperelastic.h): the law's own entry builds it.
#include "tissue_trainer/core/model/law_model_factory.h"

namespace tt {

void registerHyperelasticModel(Registry& registry) {
  ForceModelEntry e;
  e.name = kLawModel;
  e.description = "any registered material law on the mesh's tets (1 point) and hexes "
                  "(trilinear, 2x2x2 Gauss points)";
  e.keys = {{"law", "the material law (see the laws listed below), required"}};
  for (KeyDoc& key : lawOptionKeys()) e.keys.push_back(std::move(key));
  // Each standalone law adds its preset hyperelastic_LAW when it registers (Registry::add).
  e.coversHexes = true;
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    const LawEntry& law = tt::registry().law(spec["law"]);
    LawModelRequest request;
    request.options = readLawOptions(spec);
    if (context.mesh.tets.empty() && context.mesh.hexes.empty())
      spec.fail("the mesh has no tetrahedra or hexahedra");
    try {
      return law.makeModel(context, request);
    } catch (const std::invalid_argument& e) {  // an element inverted or flat at rest
      spec.fail(e.what());
    }
  };
  registry.add(std::move(e));
}

}  // namespace tt
