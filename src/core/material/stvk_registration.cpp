// Registers the law stvk (material/stvk.h).
#include "tissue_trainer/core/material/stvk.h"
#include "tissue_trainer/core/model/law_model_factory.h"

namespace tt {

void registerStvkLaw(Registry& registry) {
  registry.add(LawEntry{
      StvkLaw::kName,
      "transversely isotropic St Venant-Kirchhoff: the common Lame constants, the longitudinal "
      "pair along each element's fibre axis",
      {},
      lawModelFactory<StvkLaw>(
          [](const YamlEntry*, const Material& common) { return StvkLaw::constants(common); })});
}

}  // namespace tt
