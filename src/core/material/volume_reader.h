#pragma once
// The volume law's constants from one `materials` entry: volume_stiffness (required, in
// stress_unit) and volume_ratio (default 1). std::invalid_argument outside a scene (entry
// nullptr); a missing or malformed value is an InputError at the entry or the value.
#include "tissue_trainer/core/material/volume.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {

VolumeLaw::Constants readVolumeConstants(const YamlEntry* entry);

}  // namespace tt
