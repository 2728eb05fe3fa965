// Registers the law stvk (material/stvk.h).
#include "tissue_trainer/core/material/elastic_constants_reader.h"
#include "tissue_trainer/core/material/stvk.h"
#include "tissue_trainer/core/model/law_model_factory.h"

namespace tt {

void registerStvkLaw(Registry& registry) {
  registry.add(LawEntry{
      StvkLaw::kName,
      "transversely isotropic St Venant-Kirchhoff: the material's Lame constants "
      "(young_modulus/poisson_ratio or lambda/mu), the longitudinal pair along each element's "
      "fibre axis",
      {},
      lawModelFactory<StvkLaw>([](const ModelContext& context, std::size_t m) {
        return StvkLaw::constants(lameConstants(context, m, StvkLaw::kName));
      })});
}

// The element models over the law, compiled here once (model/law_model_factory.h).
template class HyperelasticModel<StvkLaw>;
template class adamss::VirtualHexahedronModel<StvkLaw>;

}  // namespace tt
