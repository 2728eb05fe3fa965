// The teran_muscle constants of a `materials` entry (teran_muscle_reader.h), apart from the
// law's registration so that the sanitizer build of the input rooms compiles it instrumented.
#include "teran_muscle_reader.h"

#include <string>

namespace tt {
namespace {

double nonNegativeStress(const YamlEntry& v, double unit) {
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
    c.A = nonNegativeStress(mr[0], unit);
    c.B = nonNegativeStress(mr[1], unit);
  }
  if (t.has("bulk")) c.K = nonNegativeStress(t["bulk"], unit);
  if (t.has("peak_stress")) c.sigmaMax = nonNegativeStress(t["peak_stress"], unit);
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

}  // namespace tt
