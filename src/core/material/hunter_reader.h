#pragma once
// The constants of the laws hunter and hunter_polynomial from one `materials` entry (its
// `hunter` and `hunter_polynomial` maps and stress_unit); Table 2.1 of "Adamss: Advanced
// Anisotropic Mass-Spring System" where a list, a map or the entry (nullptr outside a scene)
// is left out. Malformed values are an InputError at the value.
#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/hunter_polynomial.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {

HunterConstants readHunterConstants(const YamlEntry* material);
HunterPolynomialLaw::Constants readHunterPolynomialConstants(const YamlEntry* material);

}  // namespace tt
