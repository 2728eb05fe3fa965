#pragma once
// What a law's model factory (registry/registry.h: LawEntry::makeModel) is asked to build: the
// element model over the law, `hyperelastic` (model/hyperelastic.h) or `virtual_hexahedron`
// (model/adamss/virtual_hexahedron.h), with its options.
#include "tissue_trainer/core/material/law.h"
#include "tissue_trainer/core/model/adamss/virtual_hexahedron_options.h"

namespace tt {

enum class LawModelKind { kHyperelastic, kVirtualHexahedron };

struct LawModelRequest {
  LawModelKind kind = LawModelKind::kHyperelastic;
  LawOptions options;
  adamss::DeformationGradientSource deformationGradient =
      adamss::DeformationGradientSource::kShapeFunctions;  // virtual_hexahedron only
  adamss::PointForceDistribution distribution =
      adamss::PointForceDistribution::kAxes;  // virtual_hexahedron only
};

}  // namespace tt
