#pragma once
// The teran_muscle constants of one `materials` entry (its `teran_muscle` map and stress_unit;
// PhysBAM's FACE_3D defaults without one, or outside a scene when `material` is nullptr), for
// the models over the law: `hyperelastic` and `muscle_groups`.
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {

TeranMuscleLaw::Constants readTeranMuscleConstants(const YamlEntry* material);

}  // namespace tt
