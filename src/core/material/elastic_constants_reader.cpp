#include "tissue_trainer/core/material/elastic_constants_reader.h"

namespace tt {
namespace {

double poissonRatio(const YamlEntry& e) {
  const double nu = e.number();
  if (nu <= -1.0 || nu >= 0.5) e.fail("expected a Poisson ratio in (-1, 0.5)");
  return nu;
}

// One key of a pair that needs the other: an error naming the missing one.
void requirePair(const YamlEntry& material, const char* given, const char* missing,
                 const std::string& reader, const char* expected) {
  if (material.has(given) && !material.has(missing))
    material.fail(std::string("missing ") + missing + ", which " + reader + " reads beside " +
                  given + ": expected " + expected);
}

ElasticConstants fromYoungModulus(const YamlEntry& m, const std::string& reader, double unit) {
  requirePair(m, "young_modulus", "poisson_ratio", reader, "a Poisson ratio in (-1, 0.5)");
  requirePair(m, "poisson_ratio", "young_modulus", reader, "a Young's modulus > 0");
  for (const char* key : {"lambda_longitudinal", "mu_longitudinal"})
    if (m.has(key))
      m[key].fail("expected young_modulus_longitudinal/poisson_ratio_longitudinal beside "
                  "young_modulus/poisson_ratio (lambda_longitudinal goes with lambda/mu)");
  const double E = m["young_modulus"].positive() * unit;
  const double nu = poissonRatio(m["poisson_ratio"]);
  const double EL = m.has("young_modulus_longitudinal")
                        ? m["young_modulus_longitudinal"].positive() * unit : E;
  const double nuL = m.has("poisson_ratio_longitudinal")
                         ? poissonRatio(m["poisson_ratio_longitudinal"]) : nu;
  return ElasticConstants::transverselyIsotropic(E, nu, EL, nuL);
}

ElasticConstants fromLame(const YamlEntry& m, const std::string& reader, double unit) {
  requirePair(m, "mu", "lambda", reader, "Lame's first constant lambda (Pa or stress_unit)");
  requirePair(m, "lambda", "mu", reader, "the shear modulus mu > 0");
  for (const char* key : {"young_modulus_longitudinal", "poisson_ratio_longitudinal"})
    if (m.has(key))
      m[key].fail("expected lambda_longitudinal/mu_longitudinal beside lambda/mu "
                  "(young_modulus_longitudinal goes with young_modulus/poisson_ratio)");
  ElasticConstants k;
  k.lambda = m["lambda"].number() * unit;
  k.mu = m["mu"].positive() * unit;
  if (3.0 * k.lambda + 2.0 * k.mu <= 0.0) m["lambda"].fail("expected 3 lambda + 2 mu > 0");
  k.lambdaL = m.has("lambda_longitudinal") ? m["lambda_longitudinal"].number() * unit : k.lambda;
  k.muL = m.has("mu_longitudinal") ? m["mu_longitudinal"].positive() * unit : k.mu;
  return k;
}

}  // namespace

const std::vector<std::string>& elasticConstantKeys() {
  static const std::vector<std::string> keys{
      "young_modulus", "poisson_ratio", "young_modulus_longitudinal", "poisson_ratio_longitudinal",
      "lambda",        "mu",            "lambda_longitudinal",        "mu_longitudinal"};
  return keys;
}

bool givesElasticConstants(const YamlEntry& material) {
  for (const std::string& key : elasticConstantKeys())
    if (material.has(key.c_str())) return true;
  return false;
}

ElasticConstants readElasticConstants(const YamlEntry& m, const std::string& reader) {
  const bool young = m.has("young_modulus") || m.has("poisson_ratio");
  const bool lame = m.has("lambda") || m.has("mu");
  if (young && lame) m.fail("give either young_modulus/poisson_ratio or lambda/mu, not both");
  if (!young && !lame)
    m.fail("missing young_modulus and poisson_ratio (or lambda and mu), which " + reader +
           " reads: expected a Young's modulus > 0 and a Poisson ratio in (-1, 0.5)");
  const double unit = m.has("stress_unit") ? stressUnit(m["stress_unit"]) : 1.0;
  return young ? fromYoungModulus(m, reader, unit) : fromLame(m, reader, unit);
}

const ElasticConstants& lameConstants(const ModelContext& context, std::size_t m,
                                      const std::string& reader) {
  auto& cache = context.elasticRead;
  if (cache.size() < context.materials.size()) cache.resize(context.materials.size());
  std::optional<ElasticConstants>& read = cache.at(m);
  if (!read) {
    if (const YamlEntry* spec = context.entry(m))
      read = readElasticConstants(*spec, reader);
    else if (context.materials[m].elastic)
      read = context.materials[m].elastic;
    else
      throw std::invalid_argument(reader + ": material " + std::to_string(m) +
                                  " gives no Lame constants");
  }
  return *read;
}

std::vector<Material> withLameConstants(const ModelContext& context, const std::string& reader) {
  std::vector<Material> out = context.materials;
  for (std::size_t m = 0; m < out.size(); ++m) out[m].elastic = lameConstants(context, m, reader);
  return out;
}

}  // namespace tt
