#pragma once
// What a force model is built over: the mesh, the materials and, in a scene, the `materials`
// entries from which each law reads its own constants. The registry hands it to the force
// model and law factories (registry/registry.h).
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "tissue_trainer/core/material/elastic_constants.h"
#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/model/material.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {

// materialEntries are the scene's `materials` entries, one per material id (index =
// Mesh::material value); it is empty when the model is built outside a scene (benchmarks,
// `tissue_cli forces --model`), where the Lame constants come from Material::elastic
// (material/elastic_constants_reader.h: lameConstants).
struct ModelContext {
  ModelContext(const Mesh& mesh, const std::vector<Material>& materials,
               std::vector<YamlEntry> materialEntries = {})
      : mesh(mesh), materials(materials), materialEntries(std::move(materialEntries)) {}

  const Mesh& mesh;
  const std::vector<Material>& materials;
  std::vector<YamlEntry> materialEntries;

  // The `materials` entry of material m, nullptr outside a scene.
  const YamlEntry* entry(std::size_t m) const {
    return m < materialEntries.size() ? &materialEntries[m] : nullptr;
  }

  // Young's modulus and Poisson ratio of the one material a tissue preset is made of
  // (Material::moduli); std::invalid_argument naming the preset otherwise.
  IsotropicModuli tissueModuli(const std::string& preset) const {
    if (materials.size() != 1 || !materials[0].moduli)
      throw std::invalid_argument("preset '" + preset +
                                  "' expects one material with a Young's modulus and a Poisson "
                                  "ratio (Material::isotropic), got " +
                                  std::to_string(materials.size()) + " material(s)" +
                                  (materials.size() == 1 ? " without them" : ""));
    return *materials[0].moduli;
  }

  // The Lame constants read so far, per material id (lameConstants reads each entry once; the
  // scene loader copies them into its materials).
  mutable std::vector<std::optional<ElasticConstants>> elasticRead;
};

}  // namespace tt
