#pragma once
// The registry's factory of the element models over one law (`hyperelastic` and
// `virtual_hexahedron`), for the law's registration file: `readConstants` makes the law's
// constants of one material from its `materials` entry (nullptr outside a scene) and its common
// elastic constants.
#include <functional>
#include <memory>
#include <vector>

#include "tissue_trainer/core/model/adamss/virtual_hexahedron.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/scene/registry.h"

namespace tt {

template <class Law>
using LawConstantsReader =
    std::function<typename Law::Constants(const YamlEntry* material, const Material& common)>;

template <class Law>
LawModelFactory lawModelFactory(LawConstantsReader<Law> readConstants) {
  return [readConstants](const ModelContext& context,
                         const LawModelRequest& request) -> std::unique_ptr<ForceModel> {
    std::vector<typename Law::Constants> constants;
    for (std::size_t m = 0; m < context.materials.size(); ++m) {
      const YamlEntry* entry =
          m < context.materialEntries.size() ? &context.materialEntries[m] : nullptr;
      constants.push_back(readConstants(entry, context.materials[m]));
    }
    if (request.kind == LawModelKind::kVirtualHexahedron)
      return std::make_unique<adamss::VirtualHexahedronModel<Law>>(
          context.mesh, constants, request.options, request.deformationGradient,
          request.distribution);
    return std::make_unique<HyperelasticModel<Law>>(context.mesh, constants, request.options);
  };
}

// The options every element model over a law reads from its scene entry
// (inversion_threshold, psd_projection), and their key documentation.
LawOptions readLawOptions(const YamlEntry& spec);
std::vector<KeyDoc> lawOptionKeys();

}  // namespace tt
