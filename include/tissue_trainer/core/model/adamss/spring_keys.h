#pragma once
// The scene keys the Adamss spring models share (their registration files).
#include <array>
#include <memory>
#include <stdexcept>

#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace adamss {

KeyDoc springStressUnitKey();

// `stiffness`: three lists of 1 to 3 finite numbers (the coefficients of orders 1, 2, 3; the
// missing ones 0), scaled by `stress_unit` when `area` is true. Fails at the offending entry.
std::array<std::array<double, 3>, 3> readSpringCoefficients(const YamlEntry& spec, bool area);

// The model over the context's mesh, its construction errors (an element whose axes cannot be
// built) reported at the entry.
template <class Model, class Parameters>
std::unique_ptr<ForceModel> makeSpringModel(const YamlEntry& spec, const ModelContext& context,
                                            const Parameters& parameters) {
  if (context.mesh.tets.empty() && context.mesh.hexes.empty())
    spec.fail("the mesh has no tetrahedra or hexahedra");
  try {
    return std::make_unique<Model>(context.mesh, parameters);
  } catch (const std::invalid_argument& e) {
    spec.fail(e.what());
  }
}

}  // namespace adamss
}  // namespace tt
