#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

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
std::vector<CorruptElement> corruptElements(const Mesh& mesh,
                                            const Eigen::Ref<const Eigen::Matrix3Xd>& x,
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
FaceArea hexFaceArea(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Hex& h, int face);

// Volume of a hex as the sum of the signed volumes of its six- or five-tet split (Sec. 2.9.1);
// equals hexVolume when the faces are planar.
double hexVolumeFromTets(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Hex& h,
                         bool sixTets = true);

}  // namespace tt
