// Registers adamss_axis_friction (model/adamss/axis_friction.h).
#include "tissue_trainer/core/model/adamss/axis_friction.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

void registerAxisFrictionModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "adamss_axis_friction";
  e.description = "Adamss material friction on the rate of change of each element's axis "
                  "lengths (Eqs. 2.108-2.111), with its velocity Jacobian";
  e.keys = {{"coefficient",
             "k_d > 0, required: N s/m (bourguignon) or Pa s/m (area, virtual_hexahedron)"},
            {"form",
             "bourguignon (default, Eq. 2.108), area (Eqs. 2.109-2.110, the rest face area) or "
             "virtual_hexahedron (Eq. 2.111)"}};
  e.coversHexes = true;
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    using Form = adamss::AxisFrictionForm;
    Form form = Form::kBourguignon;
    if (spec.has("form")) {
      const std::string name = spec["form"].choice({"bourguignon", "area", "virtual_hexahedron"});
      form = name == "area" ? Form::kArea
                            : name == "virtual_hexahedron" ? Form::kVirtualHexahedron : form;
    }
    const double coefficient = spec["coefficient"].positive();
    if (context.mesh.tets.empty() && context.mesh.hexes.empty())
      spec.fail("the mesh has no tetrahedra or hexahedra");
    try {
      return std::make_unique<adamss::AxisFrictionModel>(context.mesh, coefficient, form);
    } catch (const std::invalid_argument& e) {
      spec.fail(e.what());
    }
  };
  registry.add(std::move(e));
}

}  // namespace tt
