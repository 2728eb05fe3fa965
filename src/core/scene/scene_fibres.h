#pragma once
// The fibre frames of a scene (docs/scene_format.md, "Fibres"): the top-level `fibres` entry
// for every element, then the `fibres` of each `materials` entry for the elements of that
// material. Elements are numbered tets first, then hexes.
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <vector>

#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {

// Where the loader put the mesh, x_world = rotation (scale x) + translation (the rotation turns
// the rows of a fibre file, which are in the mesh file's coordinates), and the shape of a
// truncated_ellipsoid generator, which the `ellipsoid` form reads.
struct FibreGeometry {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  std::optional<EllipsoidShape> ellipsoid;
};

void applySceneFibres(const YamlEntry& spec, const std::filesystem::path& sceneDir,
                      const FibreGeometry& geometry, Mesh& mesh);

// One `fibres` entry (direction, sheet, angles_deg or transmural; no file, no ellipsoid) for
// `elements` (tets first, then hexes) of `mesh`.
void applyFibres(const YamlEntry& spec, const std::vector<int>& elements, Mesh& mesh);

// After the materials are assigned (mesh.material, mesh.hexMaterial).
void applyMaterialFibres(const YamlEntry& materialList, const FibreGeometry& geometry, Mesh& mesh);

}  // namespace tt
