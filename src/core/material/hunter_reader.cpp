// The hunter and hunter_polynomial constants of a `materials` entry (hunter_reader.h), apart
// from the laws' registration so that the sanitizer build of the input rooms compiles them
// instrumented.
#include "hunter_reader.h"

#include <array>
#include <string>

namespace tt {
namespace {

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

}  // namespace

HunterConstants readHunterConstants(const YamlEntry* material) {
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

HunterPolynomialLaw::Constants readHunterPolynomialConstants(const YamlEntry* entry) {
  HunterPolynomialLaw::Constants c;
  c.hunter = readHunterConstants(entry);
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
}

}  // namespace tt
