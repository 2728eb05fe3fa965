#pragma once
// The fibre frames of a scene (docs/scene_format.md, "Fibres"): the top-level `fibres` entry
// for every element, then the `fibres` of each `materials` entry for the elements of that
// material. Elements are numbered tets first, then hexes.
#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {

// `meshRotation` turns the rows of a fibre file, which are in the mesh file's coordinates.
void applySceneFibres(const YamlEntry& spec, const std::filesystem::path& sceneDir,
                      const Eigen::Matrix3d& meshRotation, Mesh& mesh);

// One `fibres` entry (direction, sheet, angles_deg or transmural; no file) for `elements`
// (tets first, then hexes) of `mesh`.
void applyFibres(const YamlEntry& spec, const std::vector<int>& elements, Mesh& mesh);

// After the materials are assigned (mesh.material, mesh.hexMaterial).
void applyMaterialFibres(const YamlEntry& materialList, Mesh& mesh);

}  // namespace tt
