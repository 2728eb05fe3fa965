#pragma once
// The Lame constants of one `materials` entry, read by the laws and models that use them
// (stvk, neo_hookean, tensor_mass, edge_length, stvk_displacement) when they are created:
//   young_modulus: E, poisson_ratio: nu [, young_modulus_longitudinal, poisson_ratio_longitudinal]
// or
//   lambda, mu [, lambda_longitudinal, mu_longitudinal]
// in the entry's stress_unit (Pa without one). Other laws read their own keys, so a material
// of theirs states none of these.
#include <string>
#include <vector>

#include "tissue_trainer/core/material/elastic_constants.h"
#include "tissue_trainer/core/model/material.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {

// The keys above, in the order the docs list them.
const std::vector<std::string>& elasticConstantKeys();

// True when the entry gives any of elasticConstantKeys().
bool givesElasticConstants(const YamlEntry& material);

// The constants `reader` (a law or model name) needs; an InputError at the entry that names the
// missing key and what was expected, e.g. "missing poisson_ratio, which stvk reads beside
// young_modulus: expected a Poisson ratio in (-1, 0.5)".
ElasticConstants readElasticConstants(const YamlEntry& material, const std::string& reader);

// The Lame constants of material m of a model's context for `reader`: in a scene read once from
// its entry (an InputError there naming the missing key; context.elasticRead remembers them),
// else Material::elastic (std::invalid_argument when unset).
const ElasticConstants& lameConstants(const ModelContext& context, std::size_t m,
                                      const std::string& reader);
// The context's materials with their Lame constants set, for models that take
// std::vector<Material>.
std::vector<Material> withLameConstants(const ModelContext& context, const std::string& reader);

}  // namespace tt
