#pragma once
// Mesh quality report: counts, extent, element volumes and shape, inverted and degenerate
// elements, duplicate and unused nodes. tissue_cli info prints formatQuality().
#include <string>
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

struct QualityOptions {
  // Two nodes are duplicates when closer than this; <= 0 means 1e-9 x bounding-box diagonal.
  double duplicateTolerance = 0.0;
  // A tet is degenerate (a sliver or flat) when its normalised volume
  // 6 sqrt(2) |V| / Lmax^3 (1 for the regular tet, Lmax = longest edge) is below this.
  double degenerateVolume = 1e-3;
};

struct MeshQuality {
  int nodes = 0, tets = 0, hexes = 0, surfaceTriangles = 0;
  Box box{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  // Signed element volumes (tets and hexes; a hex volume is the exact integral of its
  // trilinear map's Jacobian determinant).
  double volumeMin = 0.0, volumeMax = 0.0, volumeTotal = 0.0;
  // Tet aspect ratio Lmax / (2 sqrt(6) r), r = inradius = 3|V| / (sum of face areas):
  // 1 for the regular tet, growing without bound as a tet flattens (infinite when V = 0).
  double aspectMin = 0.0, aspectMedian = 0.0, aspectMax = 0.0;
  int inverted = 0;     // volume < 0 and not degenerate (a hex: any tet of its six-tet split)
  int degenerate = 0;   // tets with normalised volume below QualityOptions::degenerateVolume
  int duplicateNodes = 0;  // nodes lying within the tolerance of an earlier node
  int unusedNodes = 0;     // nodes referenced by no tet or hex
};

// Aspect ratio of one tet (see MeshQuality::aspectMin); +inf for a zero-volume tet.
double tetAspectRatio(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Tet& t);
// 6 sqrt(2) |V| / Lmax^3: 1 for the regular tet, 0 for a flat one.
double tetNormalisedVolume(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Tet& t);
// Volume of a hex (VTK/Gmsh node order) by 2x2x2 Gauss quadrature of det J (exact).
double hexVolume(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Hex& h);

MeshQuality meshQuality(const Mesh& mesh, const QualityOptions& options = {});

// The shortest edge of any tet or hex (hex edges in VTK/Gmsh node order), m; +inf without
// elements. L of the critical step h_c = L / c ("Adamss: Advanced Anisotropic Mass-Spring
// System", Sec. 2.5.6, Eq. 2.150).
double shortestEdge(const Mesh& mesh);

// A few readable lines (each ending in '\n') for `tissue_cli info`.
std::string formatQuality(const MeshQuality& quality);

// Tets flat to round-off: normalised volume below kFlatTetVolume. Such a tet has no mass and
// a singular element matrix, so a scene refuses it (or drops it: mesh.drop_degenerate).
constexpr double kFlatTetVolume = 1e-6;
std::vector<int> flatTets(const Mesh& mesh);  // ascending indices
// Removes the given tets (ascending indices) with their fibre frames and materials.
void removeTets(Mesh& mesh, const std::vector<int>& tets);
// Nodes that no tet or hex uses (ascending).
std::vector<int> unusedNodes(const Mesh& mesh);

// Swaps nodes 1 and 2 of every tet with negative rest volume; returns how many were swapped.
// Fibre frames and materials are per element and stay attached to their tet.
int repairInverted(Mesh& mesh);

}  // namespace tt
