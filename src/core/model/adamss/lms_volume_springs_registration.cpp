// Registers adamss_lms_volume_springs (model/adamss/lms_volume_springs.h).
#include "tissue_trainer/core/model/adamss/lms_volume_springs.h"
#include "tissue_trainer/core/model/adamss/spring_keys.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

void registerLmsVolumeSpringModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "adamss_lms_volume_springs";
  e.description = "Adamss adaptive volume springs on tets (Eqs. 2.80-2.81): Bourguignon's tet "
                  "spring with a stiffness per tet adapted each step by least mean squares";
  e.keys = {{"stiffness", "the initial k_e > 0 in N/m, required"},
            {"rate", "the LMS step size mu >= 0 in N/m^5, required"},
            {"update",
             "strain (default): k += mu dV (sum|xi| - sum|xi0|); printed: k += mu dV sum|xi| "
             "as Eq. 2.81 prints it (softens compressed tets)"},
            {"form",
             "printed (default): the forces on the nodes as printed; gradient: less their "
             "mean, the gradient of k_e/2 (sum|xi| - sum|xi0|)^2"}};
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    adamss::LmsVolumeSpringParameters p;
    p.stiffness = spec["stiffness"].positive();
    const YamlEntry rate = spec["rate"];
    p.rate = rate.number();
    if (!(p.rate >= 0.0)) rate.fail("expected a rate >= 0, got '" + rate.node().Scalar() + "'");
    p.printedUpdate =
        spec.has("update") && spec["update"].choice({"strain", "printed"}) == "printed";
    p.gradient = spec.has("form") && spec["form"].choice({"printed", "gradient"}) == "gradient";
    return adamss::makeSpringModel<adamss::LmsVolumeSpringModel>(spec, context, p);
  };
  registry.add(std::move(e));
}

}  // namespace tt
