// Registers the law neo_hookean (material/neo_hookean.h).
#include "tissue_trainer/core/material/neo_hookean.h"
#include "tissue_trainer/core/model/law_model_factory.h"

namespace tt {

void registerNeoHookeanLaw(Registry& registry) {
  registry.add(LawEntry{
      NeoHookeanLaw::kName,
      "compressible Neo-Hookean (isotropic; J > 0, so inverting scenes add inversion_threshold)",
      {},
      lawModelFactory<NeoHookeanLaw>([](const YamlEntry* entry, const Material& common) {
        if (entry && (common.lambdaL != common.lambda || common.muL != common.mu))
          entry->fail("neo_hookean is isotropic: expected no longitudinal constants");
        return NeoHookeanLaw::constants(common);
      })});
}

}  // namespace tt
