#include "tissue_trainer/core/model/adamss/spring_keys.h"

#include <string>

namespace tt {
namespace adamss {

KeyDoc springStressUnitKey() {
  return {"stress_unit", "the unit of the coefficients with area: true (Pa, kPa, MPa; Pa by default)"};
}

std::array<std::array<double, 3>, 3> readSpringCoefficients(const YamlEntry& spec, bool area) {
  if (spec.has("stress_unit") && !area)
    spec["stress_unit"].fail("stress_unit applies to area: true only");
  const double unit = spec.has("stress_unit") ? stressUnit(spec["stress_unit"]) : 1.0;
  const YamlEntry lists = spec["stiffness"];
  const std::size_t count = lists.size();
  if (count != 3)
    lists.fail("expected 3 lists of coefficients (one per axis or axis pair), got " +
               std::to_string(count));
  std::array<std::array<double, 3>, 3> k{};
  for (int a = 0; a < 3; ++a) {
    const YamlEntry list = lists[a];
    const std::size_t orders = list.size();
    if (orders < 1 || orders > 3)
      list.fail("expected 1 to 3 coefficients (orders 1, 2, 3), got " + std::to_string(orders));
    for (std::size_t i = 0; i < orders; ++i) k[a][i] = list[static_cast<int>(i)].number() * unit;
  }
  return k;
}

}  // namespace adamss
}  // namespace tt
