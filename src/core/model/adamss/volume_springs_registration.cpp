// Registers adamss_volume_springs (model/adamss/volume_springs.h).
#include "tissue_trainer/core/model/adamss/spring_keys.h"
#include "tissue_trainer/core/model/adamss/volume_springs.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

void registerVolumeSpringModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "adamss_volume_springs";
  e.description = "Bourguignon's volume springs between each node and its element's barycentre "
                  "(Adamss Eqs. 2.75 hexes, 2.76 tets, restoring sign); no stiffness";
  e.keys = {{"stiffness", "k_s > 0 in N/m, required"},
            {"damping", "k_d >= 0 in N s/m on the radial velocities (hexes, Eq. 2.75), default 0"},
            {"form",
             "printed (default): the forces on the nodes as printed (a net force on irregular "
             "elements); gradient: less their mean, the gradient of the springs' energy"}};
  e.coversHexes = true;
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    adamss::VolumeSpringParameters p;
    p.stiffness = spec["stiffness"].positive();
    if (spec.has("damping")) {
      const YamlEntry d = spec["damping"];
      p.damping = d.number();
      if (!(p.damping >= 0.0)) d.fail("expected a damping >= 0, got '" + d.node().Scalar() + "'");
    }
    p.gradient = spec.has("form") && spec["form"].choice({"printed", "gradient"}) == "gradient";
    return adamss::makeSpringModel<adamss::VolumeSpringModel>(spec, context, p);
  };
  registry.add(std::move(e));
}

}  // namespace tt
