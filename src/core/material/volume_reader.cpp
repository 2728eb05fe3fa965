// The volume law's constants of a `materials` entry (volume_reader.h), apart from the law's
// registration so that the sanitizer build of the input rooms compiles it instrumented.
#include "volume_reader.h"

#include <stdexcept>

namespace tt {

VolumeLaw::Constants readVolumeConstants(const YamlEntry* entry) {
  if (!entry)
    throw std::invalid_argument(
        "volume law: volume_stiffness is read from a scene's materials entry");
  if (!entry->has("volume_stiffness"))
    entry->fail("missing volume_stiffness, which volume reads: expected the stiffness p > 0 "
                "of p (det F - r)^2 in stress_unit (Pa without one)");
  const double unit = entry->has("stress_unit") ? stressUnit((*entry)["stress_unit"]) : 1.0;
  VolumeLaw::Constants k;
  k.stiffness = (*entry)["volume_stiffness"].positive() * unit;
  k.ratio = entry->positive("volume_ratio", 1.0);
  return k;
}

}  // namespace tt
