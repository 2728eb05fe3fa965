#pragma once
// The fibre frames of a scene (docs/scene_format.md, "Fibres"): the top-level `fibres` entry
// for every element, then the `fibres` of each `materials` entry for the elements of that
// material. Elements are numbered tets first, then hexes.
#include <Eigen/Core>
#include <filesystem>

#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/scene/yaml_reader.h"

namespace tt {

// `meshRotation` turns the rows of a fibre file, which are in the mesh file's coordinates.
void applySceneFibres(const YamlEntry& spec, const std::filesystem::path& sceneDir,
                      const Eigen::Matrix3d& meshRotation, Mesh& mesh);

// After the materials are assigned (mesh.material, mesh.hexMaterial).
void applyMaterialFibres(const YamlEntry& materialList, Mesh& mesh);

}  // namespace tt
