#pragma once
// The registry's factory of the element models over one law (`hyperelastic` and
// `virtual_hexahedron`), for the law's registration file: `readConstants` makes the law's
// constants of material m from the context (its `materials` entry, ModelContext::entry, nullptr
// outside a scene; or its Lame constants, ModelContext::elastic). The registration file also
// instantiates the two models over its law (`template class HyperelasticModel<Law>;`), the one
// place they are compiled.
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "tissue_trainer/core/model/adamss/virtual_hexahedron_impl.h"
#include "tissue_trainer/core/model/hyperelastic_impl.h"
#include "tissue_trainer/core/model/law_model_request.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

template <class Law>
using LawConstantsReader =
    std::function<typename Law::Constants(const ModelContext& context, std::size_t material)>;

template <class Law>
LawModelFactory lawModelFactory(LawConstantsReader<Law> readConstants) {
  return [readConstants](const ModelContext& context,
                         const LawModelRequest& request) -> std::unique_ptr<ForceModel> {
    if (!supportsPsdMethod<Law>(request.options.psdMethod))
      throw std::invalid_argument(std::string("psd_method: diagonal_blocks needs law ") +
                                  "teran_muscle or an isotropic law, not " + Law::kName +
                                  " (use psd_method: eigen)");
    std::vector<typename Law::Constants> constants;
    for (std::size_t m = 0; m < context.materials.size(); ++m)
      constants.push_back(readConstants(context, m));
    if (request.kind == LawModelKind::kVirtualHexahedron)
      return std::make_unique<adamss::VirtualHexahedronModel<Law>>(
          context.mesh, constants, request.options, request.deformationGradient,
          request.distribution);
    return std::make_unique<HyperelasticModel<Law>>(context.mesh, constants, request.options);
  };
}

// The options every element model over a law reads from its scene entry
// (inversion_threshold, psd_projection, psd_method), and their key documentation.
LawOptions readLawOptions(const YamlEntry& spec);
std::vector<KeyDoc> lawOptionKeys();

}  // namespace tt
