// Registers adamss_torsion_springs (model/adamss/torsion_springs.h).
#include "tissue_trainer/core/model/adamss/spring_keys.h"
#include "tissue_trainer/core/model/adamss/torsion_springs.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

void registerTorsionSpringModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "adamss_torsion_springs";
  e.description = "Adamss springs on the angles between each element's axes (Eqs. 2.40-2.55); "
                  "stiffness in the gradient form only (the printed form: explicit integrators)";
  e.keys = {{"stiffness",
             "required: three lists (pairs fibre-sheet, fibre-normal, sheet-normal) of 1 to 3 "
             "coefficients k_1.. of orders 1..3"},
            {"measure", "angle (default, Eqs. 2.40-2.43, 2.47-2.54) or cosine (Eqs. 2.44-2.45)"},
            {"form",
             "printed (default): the forces as printed, along the other axis (no energy; a net "
             "moment unless the axes are equally long); gradient: the forces of the energy "
             "s sum k_i theta^(i+1)/(i+1)"},
            {"area",
             "true: printed forces scaled by the rest face area projected on the axis (k in "
             "stress_unit, Eq. 2.55), gradient energy scaled by the element volume (k in "
             "stress_unit); false (default): k in N (printed) or J (gradient)"},
            adamss::springStressUnitKey()};
  e.coversHexes = true;
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    adamss::TorsionSpringParameters p;
    p.areaForm = spec.boolean("area", false);
    p.cosine = spec.has("measure") && spec["measure"].choice({"angle", "cosine"}) == "cosine";
    p.gradient = spec.has("form") && spec["form"].choice({"printed", "gradient"}) == "gradient";
    p.k = adamss::readSpringCoefficients(spec, p.areaForm);
    return adamss::makeSpringModel<adamss::TorsionSpringModel>(spec, context, p);
  };
  registry.add(std::move(e));
}

}  // namespace tt
