// Registers the law teran_muscle (material/teran_muscle.h). It reads a material's map
//   teran_muscle: {mooney_rivlin: [A, B], bulk: K, peak_stress: S, activation: alpha,
//                  fiber_stretch: deviatoric | nondeviatoric}
// with A, B, K and S in the entry's stress_unit (Pa when it has none); a key left out keeps
// PhysBAM's FACE_3D default (A 6e4, B 2e4, K 6e4, S 3e5 Pa, alpha 0, deviatoric).
#include <string>

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

double nonNegative(const YamlEntry& v, double unit) {
  const double x = v.number();
  if (!(x >= 0.0)) v.fail("expected a stress >= 0, got '" + v.node().Scalar() + "'");
  return x * unit;
}

}  // namespace

TeranMuscleLaw::Constants readTeranMuscleConstants(const YamlEntry* material) {
  TeranMuscleLaw::Constants c;
  if (!material || !material->has("teran_muscle")) return c;
  const YamlEntry t = (*material)["teran_muscle"];
  t.expectMap({"mooney_rivlin", "bulk", "peak_stress", "activation", "fiber_stretch"});
  const double unit = material->has("stress_unit") ? stressUnit((*material)["stress_unit"]) : 1.0;
  if (t.has("mooney_rivlin")) {
    const YamlEntry mr = t["mooney_rivlin"];
    if (mr.size() != 2)
      mr.fail("expected a list of 2 numbers A, B, got " + std::to_string(mr.size()));
    c.A = nonNegative(mr[0], unit);
    c.B = nonNegative(mr[1], unit);
  }
  if (t.has("bulk")) c.K = nonNegative(t["bulk"], unit);
  if (t.has("peak_stress")) c.sigmaMax = nonNegative(t["peak_stress"], unit);
  if (t.has("activation")) {
    const YamlEntry a = t["activation"];
    c.activation = a.number();
    if (!(c.activation >= 0.0 && c.activation <= 1.0))
      a.fail("expected an activation in [0, 1], got '" + a.node().Scalar() + "'");
  }
  if (t.has("fiber_stretch"))
    c.deviatoricStretch = t["fiber_stretch"].choice({"deviatoric", "nondeviatoric"}) == "deviatoric";
  return c;
}

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

}  // namespace tt
