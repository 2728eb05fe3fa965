#pragma once
// The nodes and elements a scene entry names (boundary sets, material and muscle regions,
// collision surfaces, cavity walls). Read by the scene loader and by the models' registrations,
// which need no more of the loader than this.
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {

// The nodes a selection names: {box: {min, max}}, {plane: {point, normal, tolerance}},
// {nodes: [indices]} (rest positions; indices are the mesh file's numbers). An empty result is
// an error at the entry.
std::vector<int> selectNodes(const YamlEntry& spec, const Mesh& mesh);
// The elements (numbered tets first, then hexes) a region names: `all`, {box: {min, max}}
// (element centroids at rest) or {elements: [indices]} (the file's numbers); sorted, each once.
// A box that holds no centroid is an error at the entry.
std::vector<int> regionElements(const YamlEntry& region, const Mesh& mesh);

// Element e (tets first, then hexes) of the mesh's file in the mesh, and back (hexes keep their
// file order; mesh.numbering).
int elementFromFile(const Mesh& mesh, int e);
int elementToFile(const Mesh& mesh, int e);

}  // namespace tt
