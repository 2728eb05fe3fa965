// Registers the law guccione (material/guccione.h), its constants read from a material's
//   guccione: {C, b_f, b_t, b_fs, bulk_modulus}   (guccione_reader.h).
#include <cstddef>

#include "tissue_trainer/core/material/guccione.h"
#include "tissue_trainer/core/model/law_model_factory.h"
#include "guccione_reader.h"

namespace tt {

void registerGuccioneLaw(Registry& registry) {
  registry.add(LawEntry{
      GuccioneLaw::kName,
      "transversely isotropic Guccione law C/2 (e^Q - 1) of passive myocardium (the cardiac "
      "mechanics benchmark of Land et al. 2015) in each element's fibre frame, with the "
      "volumetric penalty kappa/2 (J - 1)^2",
      {{"guccione",
        "{C: > 0 in stress_unit, b_f, b_t, b_fs: >= 0, bulk_modulus: kappa > 0 in stress_unit}, "
        "all required: Q = b_f E_ff^2 + b_t (E_ss^2 + E_nn^2 + 2 E_sn^2) + 2 b_fs (E_fs^2 + "
        "E_fn^2) in the fibre frame"}},
      lawModelFactory<GuccioneLaw>([](const ModelContext& context, std::size_t m) {
        return readGuccioneConstants(context.entry(m));
      })});
}

// The element models over the law, compiled here once (model/law_model_factory.h).
template class HyperelasticModel<GuccioneLaw>;
template class adamss::VirtualHexahedronModel<GuccioneLaw>;

}  // namespace tt
