// Registers hyperelastic (model/hyperelastic.h): the law's own entry builds it.
#include <cmath>
#include <stdexcept>

#include "tissue_trainer/core/scene/registry.h"

namespace tt {

void registerHyperelasticModel(Registry& registry) {
  ForceModelEntry e;
  e.name = kLawModel;
  e.description = "any registered material law on the mesh's tets (1 point) and hexes "
                  "(trilinear, 2x2x2 Gauss points)";
  e.keys = {{"law", "the material law (see the laws listed below), required"},
            {"inversion_threshold",
             "eps >= 0: singular values of F clamped at eps, so inverted elements push back "
             "(0, the default, turns it off)"},
            {"psd_projection",
             "true: the stiffness and stiffness products use the law's tangent with negative "
             "eigenvalues removed (default false)"}};
  // Each standalone law adds its preset hyperelastic_LAW when it registers (Registry::add).
  e.coversHexes = true;
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    const LawEntry& law = tt::registry().law(spec["law"]);
    LawOptions options;
    if (spec.has("inversion_threshold")) {
      const YamlEntry eps = spec["inversion_threshold"];
      options.inversionThreshold = eps.number();
      if (!(options.inversionThreshold >= 0.0 && options.inversionThreshold < 1.0))
        eps.fail("expected a threshold in [0, 1) (a singular value of F; 0 turns it off)");
    }
    options.psdProjection = spec.boolean("psd_projection", false);
    if (context.mesh.tets.empty() && context.mesh.hexes.empty())
      spec.fail("the mesh has no tetrahedra or hexahedra");
    try {
      return law.makeHyperelastic(context, options);
    } catch (const std::invalid_argument& e) {  // an element inverted or flat at rest
      spec.fail(e.what());
    }
  };
  registry.add(std::move(e));
}

}  // namespace tt
