// Registers adamss_active_tension (model/adamss/active_tension.h).
#include "tissue_trainer/core/model/adamss/active_tension.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

void registerActiveTensionModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "adamss_active_tension";
  e.description = "Adamss active contraction (Eqs. 2.112-2.116): a tension following a time "
                  "curve, along each element's fibre or isotropic over its faces";
  e.keys = {{"curve",
             "required: the tension over time, {type: constant | piecewise_linear | twitch, ...} "
             "(docs/scene_format.md); positive contracts"},
            {"form", "anisotropic (default: along the fibre axis, Eqs. 2.113-2.116) or isotropic "
                     "(every face, Eq. 2.112)"},
            {"mode", "tension (default: per current area) or force (per rest area)"},
            {"stress_unit", "unit of the curve's values: Pa (default), kPa or MPa"}};
  e.coversHexes = true;
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    using adamss::ActiveForm;
    using adamss::ActiveMode;
    const ActiveForm form =
        spec.has("form") && spec["form"].choice({"anisotropic", "isotropic"}) == "isotropic"
            ? ActiveForm::kIsotropic
            : ActiveForm::kAnisotropic;
    const ActiveMode mode = spec.has("mode") && spec["mode"].choice({"tension", "force"}) == "force"
                                ? ActiveMode::kForce
                                : ActiveMode::kTension;
    const double unit = spec.has("stress_unit") ? stressUnit(spec["stress_unit"]) : 1.0;
    TimeCurve curve = readTimeCurve(spec["curve"], unit);
    if (context.mesh.tets.empty() && context.mesh.hexes.empty())
      spec.fail("the mesh has no tetrahedra or hexahedra");
    try {
      return std::make_unique<adamss::ActiveTensionModel>(context.mesh, form, mode,
                                                          std::move(curve));
    } catch (const std::invalid_argument& e) {
      spec.fail(e.what());
    }
  };
  registry.add(std::move(e));
}

}  // namespace tt
