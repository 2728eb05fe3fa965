// The guccione constants of a `materials` entry (guccione_reader.h), apart from the law's
// registration so that the sanitizer build of the input rooms compiles them instrumented.
#include "guccione_reader.h"

#include <string>

namespace tt {
namespace {

const char* const kGuccioneKeys =
    "guccione: {C, b_f, b_t, b_fs, bulk_modulus} (C and bulk_modulus in stress_unit)";

double guccioneNumber(const YamlEntry& map, const char* key, bool allowZero, const char* what) {
  if (!map.has(key))
    map.fail(std::string("missing ") + key + ", which guccione reads: expected " + what);
  const YamlEntry value = map[key];
  const double v = value.number();
  if (!(allowZero ? v >= 0.0 : v > 0.0))
    value.fail(std::string("expected ") + key + " " + (allowZero ? ">= 0" : "> 0") + " (" +
               what + "), got '" + value.node().Scalar() + "'");
  return v;
}

}  // namespace

GuccioneConstants readGuccioneConstants(const YamlEntry* material) {
  // Outside a scene (the preset hyperelastic_guccione): the benchmark's beam, kappa = 50 C.
  if (!material) return GuccioneConstants::landBeam(1e5);
  if (!material->has("guccione"))
    material->fail(std::string("missing guccione, which the guccione law reads: expected ") +
                   kGuccioneKeys);
  const YamlEntry g = (*material)["guccione"];
  g.expectMap({"C", "b_f", "b_t", "b_fs", "bulk_modulus"});
  const double unit = material->has("stress_unit") ? stressUnit((*material)["stress_unit"]) : 1.0;
  GuccioneConstants c;
  c.C = guccioneNumber(g, "C", false, "the stiffness C of C/2 (e^Q - 1)") * unit;
  c.bf = guccioneNumber(g, "b_f", true, "the fibre exponent weight");
  c.bt = guccioneNumber(g, "b_t", true, "the transverse exponent weight");
  c.bfs = guccioneNumber(g, "b_fs", true, "the fibre-transverse shear exponent weight");
  c.bulkModulus = guccioneNumber(g, "bulk_modulus", false,
                                 "kappa of the penalty kappa/2 (J - 1)^2") * unit;
  return c;
}

}  // namespace tt
