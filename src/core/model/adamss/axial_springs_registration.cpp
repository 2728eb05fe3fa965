// Registers adamss_axial_springs (model/adamss/axial_springs.h).
#include "tissue_trainer/core/model/adamss/axial_springs.h"
#include "tissue_trainer/core/model/adamss/spring_keys.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

void registerAxialSpringModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "adamss_axial_springs";
  e.description = "Adamss polynomial springs along each element's fibre, sheet and sheet-normal "
                  "axes, between the axes' intersection points (Eqs. 2.35-2.39)";
  e.keys = {{"stiffness",
             "required: three lists (fibre, sheet, sheet-normal) of 1 to 3 coefficients k_1.. of "
             "orders 1..3; N/m^i, or stress_unit with area: true"},
            {"area",
             "true: the force is A sum k_i eps^i with eps the axis strain and A the rest face "
             "area projected on the axis (Eqs. 2.37-2.39); false (default): sum k_i d^i with d "
             "the axis's change of length (Eqs. 2.35-2.36)"},
            adamss::springStressUnitKey()};
  e.presets = {{"adamss_axial_springs_table22",
                "{area: true, stress_unit: kPa, stiffness: [[6.358, 0, 768], [0, 0, 288.525], "
                "[0.305, 0, 5.699]]}",
                "the cubic axial springs of Adamss Table 2.2 (kPa)"}};
  e.coversHexes = true;
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    adamss::AxialSpringParameters p;
    p.areaForm = spec.boolean("area", false);
    p.k = adamss::readSpringCoefficients(spec, p.areaForm);
    return adamss::makeSpringModel<adamss::AxialSpringModel>(spec, context, p);
  };
  registry.add(std::move(e));
}

}  // namespace tt
