// Registers the laws hunter (material/hunter.h) and hunter_polynomial
// (material/hunter_polynomial.h). Both read a material's `hunter` map
//   hunter: {k: [k11, k22, k33, k12, k13, k23], a: [...], b: [...]}
// with k in the entry's stress_unit (Pa when it has none); a list that is left out, or the
// whole map, takes Table 2.1 of "Adamss: Advanced Anisotropic Mass-Spring System" (k in kPa
// there, whatever the entry's stress_unit). hunter_polynomial also reads
//   hunter_polynomial: {switch_fraction: s, degree: n}.
#include <cstddef>

#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/hunter_polynomial.h"
#include "tissue_trainer/core/model/law_model_factory.h"
#include "hunter_reader.h"

namespace tt {
namespace {

const char* const kHunterKeyDoc =
    "{k: [k11, k22, k33, k12, k13, k23], a: [...], b: [...]} of Eq. 2.153 in the fibre frame: "
    "k >= 0 in stress_unit (Pa without one), poles a > 0, exponents b >= 0; a list or the whole "
    "map left out takes Table 2.1 (k in kPa)";

}  // namespace

void registerHunterLaw(Registry& registry) {
  registry.add(LawEntry{
      HunterLaw::kName,
      "Hunter pole-zero law of myocardium (Adamss Eq. 2.153) in each element's fibre frame; "
      "infinite energy beyond a pole",
      {{"hunter", kHunterKeyDoc}},
      lawModelFactory<HunterLaw>([](const ModelContext& context, std::size_t m) {
        return readHunterConstants(context.entry(m));
      })});
}

void registerHunterPolynomialLaw(Registry& registry) {
  registry.add(LawEntry{
      HunterPolynomialLaw::kName,
      "pole-free substitute of the Hunter law (Adamss Sec. 2.9.2): Eq. 2.153 below each term's "
      "switch strain, its Taylor polynomial beyond",
      {{"hunter", kHunterKeyDoc},
       {"hunter_polynomial",
        "{switch_fraction: s in (0, 1), default 0.9: each term switches at E = s a; degree: n "
        "in [2, 6], default 3: the Taylor polynomial's degree}"}},
      lawModelFactory<HunterPolynomialLaw>([](const ModelContext& context, std::size_t m) {
        return readHunterPolynomialConstants(context.entry(m));
      })});
}

// The element models over the law, compiled here once (model/law_model_factory.h).
template class HyperelasticModel<HunterLaw>;
template class adamss::VirtualHexahedronModel<HunterLaw>;
template class HyperelasticModel<HunterPolynomialLaw>;
template class adamss::VirtualHexahedronModel<HunterPolynomialLaw>;

}  // namespace tt
