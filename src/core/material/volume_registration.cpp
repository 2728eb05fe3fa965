// Registers the law volume (material/volume.h).
#include "tissue_trainer/core/material/volume.h"
#include "tissue_trainer/core/model/law_model_factory.h"
#include "volume_reader.h"

namespace tt {

void registerVolumeLaw(Registry& registry) {
  registry.add(LawEntry{
      VolumeLaw::kName,
      "volume term p (det F - r)^2: keeps (r = 1) or drives (r = V_inf / V0) the volume",
      {{"volume_stiffness", "p in Pa (scaled by stress_unit), required by the volume law"},
       {"volume_ratio", "r = V_inf / V0 > 0, default 1 (keep the rest volume)"}},
      lawModelFactory<VolumeLaw>([](const ModelContext& context, std::size_t m) {
        return readVolumeConstants(context.entry(m));
      }),
      /*standalone=*/false});
}

// The element models over the law, compiled here once (model/law_model_factory.h).
template class HyperelasticModel<VolumeLaw>;
template class adamss::VirtualHexahedronModel<VolumeLaw>;

}  // namespace tt
