#pragma once
// The registry's factory of the `hyperelastic` model over one law, for the law's registration
// file: `readConstants` makes the law's constants of one material from its `materials` entry
// (nullptr outside a scene) and its common elastic constants.
#include <functional>
#include <memory>
#include <vector>

#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/scene/registry.h"

namespace tt {

template <class Law>
using LawConstantsReader =
    std::function<typename Law::Constants(const YamlEntry* material, const Material& common)>;

template <class Law>
LawModelFactory hyperelasticFactory(LawConstantsReader<Law> readConstants) {
  return [readConstants](const ModelContext& context,
                         const LawOptions& options) -> std::unique_ptr<ForceModel> {
    std::vector<typename Law::Constants> constants;
    for (std::size_t m = 0; m < context.materials.size(); ++m) {
      const YamlEntry* entry =
          m < context.materialEntries.size() ? &context.materialEntries[m] : nullptr;
      constants.push_back(readConstants(entry, context.materials[m]));
    }
    return std::make_unique<HyperelasticModel<Law>>(context.mesh, constants, options);
  };
}

}  // namespace tt
