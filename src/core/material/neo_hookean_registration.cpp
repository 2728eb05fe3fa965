// Registers the law neo_hookean (material/neo_hookean.h).
#include "tissue_trainer/core/material/elastic_constants_reader.h"
#include "tissue_trainer/core/material/neo_hookean.h"
#include "tissue_trainer/core/model/law_model_factory.h"

namespace tt {

void registerNeoHookeanLaw(Registry& registry) {
  registry.add(LawEntry{
      NeoHookeanLaw::kName,
      "compressible Neo-Hookean (isotropic; the material's young_modulus/poisson_ratio or "
      "lambda/mu; J > 0, so inverting scenes add inversion_threshold)",
      {},
      lawModelFactory<NeoHookeanLaw>([](const ModelContext& context, std::size_t m) {
        const ElasticConstants& k = lameConstants(context, m, NeoHookeanLaw::kName);
        if (context.entry(m) && (k.lambdaL != k.lambda || k.muL != k.mu))
          context.entry(m)->fail("neo_hookean is isotropic: expected no longitudinal constants");
        return NeoHookeanLaw::constants(k);
      })});
}

// The element models over the law, compiled here once (model/law_model_factory.h).
template class HyperelasticModel<NeoHookeanLaw>;
template class adamss::VirtualHexahedronModel<NeoHookeanLaw>;

}  // namespace tt
