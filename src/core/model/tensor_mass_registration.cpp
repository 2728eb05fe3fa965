// Registers tensor_mass in the scene registry.
#include "tissue_trainer/core/material/elastic_constants_reader.h"
#include "tissue_trainer/core/model/tensor_mass.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

void registerTensorMassModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "tensor_mass";
  e.description = "linear (small-strain) transversely isotropic tetrahedron, constant stiffness";
  e.presets = {{"tensor_mass", "", "the linear model"}};
  e.make = [](const YamlEntry&, const ModelContext& c) -> std::unique_ptr<ForceModel> {
    return std::make_unique<TensorMassModel>(c.mesh, withLameConstants(c, "tensor_mass"));
  };
  registry.add(std::move(e));
}

}  // namespace tt
