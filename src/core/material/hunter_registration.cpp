// Registers the laws hunter (material/hunter.h) and hunter_polynomial
// (material/hunter_polynomial.h). Both read a material's `hunter` map
//   hunter: {k: [k11, k22, k33, k12, k13, k23], a: [...], b: [...]}
// with k in the entry's stress_unit (Pa when it has none); a list that is left out, or the
// whole map, takes Table 2.1 of "Adamss: Advanced Anisotropic Mass-Spring System" (k in kPa
// there, whatever the entry's stress_unit). hunter_polynomial also reads
//   hunter_polynomial: {switch_fraction: s, degree: n}.
#include <array>
#include <cstddef>
#include <string>

#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/hunter_polynomial.h"
#include "tissue_trainer/core/model/law_model_factory.h"

namespace tt {
namespace {

const char* const kHunterKeyDoc =
    "{k: [k11, k22, k33, k12, k13, k23], a: [...], b: [...]} of Eq. 2.153 in the fibre frame: "
    "k >= 0 in stress_unit (Pa without one), poles a > 0, exponents b >= 0; a list or the whole "
    "map left out takes Table 2.1 (k in kPa)";

// Six numbers of `list` (11, 22, 33, 12, 13, 23), each checked by `valid` (else the message
// `expected` names the term).
template <class Valid>
std::array<double, 6> sixNumbers(const YamlEntry& list, const char* symbol, Valid valid,
                                 const char* expected) {
  const std::size_t count = list.size();  // fails for a value that is not a list
  if (count != 6)
    list.fail(std::string("expected a list of 6 numbers ") + symbol + "11, " + symbol + "22, " +
              symbol + "33, " + symbol + "12, " + symbol + "13, " + symbol + "23, got " +
              std::to_string(count));
  std::array<double, 6> out{};
  for (int t = 0; t < 6; ++t) {
    const YamlEntry item = list[t];
    out[t] = item.number();
    if (!valid(out[t]))
      item.fail(std::string("expected ") + symbol + kFibreTermLabel[t] + " " + expected +
                ", got '" + item.node().Scalar() + "'");
  }
  return out;
}

HunterConstants readHunter(const YamlEntry* material) {
  HunterConstants c = HunterConstants::table21();
  if (!material || !material->has("hunter")) return c;
  const YamlEntry h = (*material)["hunter"];
  h.expectMap({"k", "a", "b"});
  if (h.has("k")) {
    const double unit =
        material->has("stress_unit") ? stressUnit((*material)["stress_unit"]) : 1.0;
    c.k = sixNumbers(h["k"], "k", [](double v) { return v >= 0.0; }, ">= 0");
    for (double& k : c.k) k *= unit;
  }
  if (h.has("a"))
    c.a = sixNumbers(h["a"], "a", [](double v) { return v > 0.0; },
                     "> 0 (the pole, a Green strain: the rest state E = 0 must lie below it)");
  if (h.has("b"))
    c.b = sixNumbers(h["b"], "b", [](double v) { return v >= 0.0; }, ">= 0 (an exponent)");
  return c;
}

}  // namespace

void registerHunterLaw(Registry& registry) {
  registry.add(LawEntry{
      HunterLaw::kName,
      "Hunter pole-zero law of myocardium (Adamss Eq. 2.153) in each element's fibre frame; "
      "infinite energy beyond a pole",
      {{"hunter", kHunterKeyDoc}},
      lawModelFactory<HunterLaw>([](const ModelContext& context, std::size_t m) {
        return readHunter(context.entry(m));
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
        const YamlEntry* entry = context.entry(m);
        HunterPolynomialLaw::Constants c;
        c.hunter = readHunter(entry);
        if (entry && entry->has("hunter_polynomial")) {
          const YamlEntry spec = (*entry)["hunter_polynomial"];
          spec.expectMap({"switch_fraction", "degree"});
          if (spec.has("switch_fraction")) {
            const YamlEntry s = spec["switch_fraction"];
            c.switchFraction = s.number();
            if (!(c.switchFraction > 0.0 && c.switchFraction < 1.0))
              s.fail("expected a fraction of the pole in (0, 1), got '" + s.node().Scalar() + "'");
          }
          if (spec.has("degree")) {
            const YamlEntry n = spec["degree"];
            c.degree = n.integerAtLeast(2);
            if (c.degree > PoleFreeTerm::kMaxDegree)
              n.fail("expected a degree in [2, " + std::to_string(PoleFreeTerm::kMaxDegree) +
                     "], got '" + n.node().Scalar() + "'");
          }
        }
        return c;
      })});
}

}  // namespace tt
