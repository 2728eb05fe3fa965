// Registers the law volume (material/volume.h).
#include "tissue_trainer/core/material/volume.h"
#include "tissue_trainer/core/model/law_model_factory.h"

namespace tt {

void registerVolumeLaw(Registry& registry) {
  registry.add(LawEntry{
      VolumeLaw::kName,
      "volume term p (det F - r)^2: keeps (r = 1) or drives (r = V_inf / V0) the volume",
      {{"volume_stiffness", "p in Pa (scaled by stress_unit), required by the volume law"},
       {"volume_ratio", "r = V_inf / V0 > 0, default 1 (keep the rest volume)"}},
      lawModelFactory<VolumeLaw>([](const ModelContext& context, std::size_t m) {
        const YamlEntry* entry = context.entry(m);
        if (!entry)
          throw std::invalid_argument(
              "volume law: volume_stiffness is read from a scene's materials entry");
        if (!entry->has("volume_stiffness"))
          entry->fail("missing volume_stiffness, which volume reads: expected the stiffness p > 0 "
                      "of p (det F - r)^2 in stress_unit (Pa without one)");
        const double unit = entry->has("stress_unit") ? stressUnit((*entry)["stress_unit"]) : 1.0;
        VolumeLaw::Constants k;
        k.stiffness = (*entry)["volume_stiffness"].positive() * unit;
        k.ratio = entry->positive("volume_ratio", 1.0);
        return k;
      }),
      /*standalone=*/false});
}

}  // namespace tt
