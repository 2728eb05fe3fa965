// Registers the law teran_muscle (material/teran_muscle.h). It reads a material's map
//   teran_muscle: {mooney_rivlin: [A, B], bulk: K, peak_stress: S, activation: alpha,
//                  fiber_stretch: deviatoric | nondeviatoric}
// with A, B, K and S in the entry's stress_unit (Pa when it has none); a key left out keeps
// PhysBAM's FACE_3D default (A 6e4, B 2e4, K 6e4, S 3e5 Pa, alpha 0, deviatoric).
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/model/law_model_factory.h"
#include "teran_muscle_reader.h"

namespace tt {
namespace {

const char* const kTeranKeyDoc =
    "{mooney_rivlin: [A, B], bulk: K, peak_stress: S (stress_unit, Pa without one; defaults "
    "6e4, 2e4, 6e4, 3e5 Pa), activation: alpha in [0, 1] (default 0), fiber_stretch: "
    "deviatoric (J^(-1/3)|F a0|, default) or nondeviatoric (|F a0|)}; the fibre is each "
    "element's fibre axis";

}  // namespace

void registerTeranMuscleLaw(Registry& registry) {
  registry.add(LawEntry{
      TeranMuscleLaw::kName,
      "active Mooney-Rivlin muscle (Bao, quasistatics for muscles, Eq. 10) along each element's "
      "fibre axis; psi(I) = 3 (A + B); J > 0, so inverting scenes add inversion_threshold "
      "(0.25 in PhysBAM)",
      {{"teran_muscle", kTeranKeyDoc}},
      lawModelFactory<TeranMuscleLaw>(
          [](const ModelContext& context, std::size_t m) {
            return readTeranMuscleConstants(context.entry(m));
          })});
}

// The element models over the law, compiled here once (model/law_model_factory.h).
template class HyperelasticModel<TeranMuscleLaw>;
template class adamss::VirtualHexahedronModel<TeranMuscleLaw>;

}  // namespace tt
