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
double tetAspectRatio(const Eigen::Matrix3Xd& x, const Tet& t);
// 6 sqrt(2) |V| / Lmax^3: 1 for the regular tet, 0 for a flat one.
double tetNormalisedVolume(const Eigen::Matrix3Xd& x, const Tet& t);
// Volume of a hex (VTK/Gmsh node order) by 2x2x2 Gauss quadrature of det J (exact).
double hexVolume(const Eigen::Matrix3Xd& x, const Hex& h);

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

// Corrupt elements ("Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.9.1). A tet is
// corrupt when its signed volume changed sign (Eq. 2.154) or fell to a small fraction of its
// rest volume (flat: the inner forces need a volume). A hex is corrupt when it is no longer a
// simple polyhedron, e.g. a node pushed through the opposite face (Fig. 2.30): a linear hex's
// faces are not determined by its nodes (Fig. 2.31), so it is checked through tet
// decompositions (Figs. 2.7-2.8), corrupt when a tet of them is inverted or flat. The check
// lives here, with the mesh, because it is geometry only: the stability guard and any force
// model can use it without depending on each other.
enum class CorruptReason { kInverted, kFlat };
// Which tet decompositions a hex is checked through: the six tets around the diagonal 0-6
// (Hex8::sixTets), the five of Hex8::fiveTets, or both (11 tets; a fold one split misses can
// show in the other).
enum class HexSplit { kSix, kFive, kBoth };

struct CorruptElement {
  bool hex = false;  // false: index is a tet's, true: a hex's
  int index = 0;
  CorruptReason reason = CorruptReason::kInverted;
  // A hex's worst tet: 0-5 of the six-tet split, 6-10 the five-tet split's 0-4; -1 for a tet.
  int subTet = -1;
  double volumeRatio = 0.0;  // signed volume / rest volume of that (sub-)tet
};

// What an element's entry says, e.g. "tet 4 inverted (volume -0.2 of rest)" or "hex 1 not a
// simple polyhedron: tet 2 of its five-tet split flat (volume 0.004 of rest)".
std::string describeCorrupt(const CorruptElement& element);

// The tets a mesh's elements are checked through, with their rest volumes, built once.
class CorruptElementCheck {
 public:
  CorruptElementCheck() = default;
  explicit CorruptElementCheck(const Mesh& mesh, HexSplit split = HexSplit::kBoth);

  // The corrupt elements at positions x (3 x n), tets then hexes in mesh order, each once
  // with its worst (sub-)tet: inverted below 0, flat in [0, minVolumeRatio] of the rest
  // volume. (Sub-)tets flat at rest are not checked. Allocates only for corrupt elements.
  std::vector<CorruptElement> find(const Eigen::Ref<const Eigen::Matrix3Xd>& x,
                                   double minVolumeRatio) const;
  bool empty() const { return tets_.empty(); }

 private:
  std::vector<Tet> tets_;      // the mesh's tets, then each hex's decomposition
  std::vector<double> rest_;   // signed rest volume per checked tet
  int numTets_ = 0;
  int perHex_ = 0;
  int firstSubTet_ = 0;        // 6 when only the five-tet split is checked, else 0
};

// One-off form of CorruptElementCheck::find, at positions x of the mesh's nodes.
std::vector<CorruptElement> corruptElements(const Mesh& mesh, const Eigen::Matrix3Xd& x,
                                            double minVolumeRatio = 0.01,
                                            HexSplit split = HexSplit::kBoth);

// A hex face (Hex8::faces order) of four points that need not be coplanar: its area as the
// mean of its two triangulations' areas (diagonal a-c and diagonal b-d), and its unit normal
// as the normalised mean of the four triangles' unit normals (Sec. 2.9.1, Fig. 2.32); outward
// for a positively oriented hex. Exact for a planar face.
struct FaceArea {
  double area = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
};
FaceArea hexFaceArea(const Eigen::Matrix3Xd& x, const Hex& h, int face);

// Volume of a hex as the sum of the signed volumes of its six- or five-tet split (Sec. 2.9.1);
// equals hexVolume when the faces are planar.
double hexVolumeFromTets(const Eigen::Matrix3Xd& x, const Hex& h, bool sixTets = true);

}  // namespace tt
