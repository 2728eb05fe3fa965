#pragma once
// The constants of the law guccione from one `materials` entry: its map
//   guccione: {C: c, b_f: .., b_t: .., b_fs: .., bulk_modulus: kappa}
// with C and bulk_modulus in the entry's stress_unit (Pa without one). Every key is required
// (the law has no customary defaults); a missing or invalid one is an InputError at the value.
// Outside a scene (material nullptr): Problem 1's constants with a bulk modulus of 100 kPa.
#include "tissue_trainer/core/material/guccione.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {

GuccioneConstants readGuccioneConstants(const YamlEntry* material);

}  // namespace tt
