#pragma once
// A thick-walled box with a box-shaped cavity, for the cavity scene tests: a grid of
// cells x cells x cells cubes of side `cell`, split into tets, with the central
// inner x inner x inner cubes removed and the nodes left without a tet dropped.
#include <algorithm>
#include <vector>

#include "tissue_trainer/core/mesh/generators.h"

namespace tt {
namespace testutil {

inline Mesh hollowBox(int cells, int inner, double cell) {
  const Mesh grid = boxGrid(cells + 1, cells + 1, cells + 1,
                            Eigen::Vector3d::Constant(cells * cell), TetSplit::kSixMirrored);
  const double lo = cell * (cells - inner) / 2.0, hi = lo + inner * cell;
  Mesh mesh;
  std::vector<int> renumber(grid.numNodes(), -1);
  std::vector<Tet> kept;
  for (const Tet& t : grid.tets) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int p : t) centroid += grid.rest.col(p) / 4.0;
    if ((centroid.array() > lo).all() && (centroid.array() < hi).all()) continue;
    kept.push_back(t);
    for (int p : t) renumber[p] = 0;
  }
  int count = 0;
  for (int& r : renumber)
    if (r == 0) r = count++;
  mesh.rest.resize(3, count);
  for (int i = 0; i < grid.numNodes(); ++i)
    if (renumber[i] >= 0) mesh.rest.col(renumber[i]) = grid.rest.col(i);
  for (Tet t : kept) {
    for (int& p : t) p = renumber[p];
    mesh.tets.push_back(t);
  }
  mesh.surface = extractSurface(mesh);
  mesh.fillDefaults();
  return mesh;
}

}  // namespace testutil
}  // namespace tt
