#include "tissue_trainer/core/mesh/corrupt_elements.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "tissue_trainer/core/element/hex8.h"

namespace tt {

namespace {

double signedTetVolume(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Tet& t) {
  const Eigen::Vector3d a = x.col(t[0]);
  return (x.col(t[1]) - a).dot((x.col(t[2]) - a).cross(x.col(t[3]) - a)) / 6.0;
}

Tet subTet(const Hex& h, const int (&local)[4]) {
  return {h[local[0]], h[local[1]], h[local[2]], h[local[3]]};
}

const char* splitName(int subTet) { return subTet < 6 ? "six-tet" : "five-tet"; }

}  // namespace

std::string describeCorrupt(const CorruptElement& c) {
  char ratio[64];
  std::snprintf(ratio, sizeof ratio, " (volume %.3g of rest)", c.volumeRatio);
  const std::string what = c.reason == CorruptReason::kInverted ? "inverted" : "flat";
  if (!c.hex) return "tet " + std::to_string(c.index) + " " + what + ratio;
  return "hex " + std::to_string(c.index) + " not a simple polyhedron: tet " +
         std::to_string(c.subTet < 6 ? c.subTet : c.subTet - 6) + " of its " +
         splitName(c.subTet) + " split " + what + ratio;
}

CorruptElementCheck::CorruptElementCheck(const Mesh& mesh, HexSplit split)
    : tets_(mesh.tets), numTets_(mesh.numTets()) {
  const bool six = split != HexSplit::kFive, five = split != HexSplit::kSix;
  perHex_ = (six ? 6 : 0) + (five ? 5 : 0);
  firstSubTet_ = six ? 0 : 6;
  for (const Hex& h : mesh.hexes) {
    if (six)
      for (const auto& local : Hex8::sixTets) tets_.push_back(subTet(h, local));
    if (five)
      for (const auto& local : Hex8::fiveTets) tets_.push_back(subTet(h, local));
  }
  rest_.resize(tets_.size());
  for (std::size_t k = 0; k < tets_.size(); ++k) rest_[k] = signedTetVolume(mesh.rest, tets_[k]);
  // A hex collapsed into a wedge (the apex cells of truncatedEllipsoid) has check tets whose
  // four corners are coplanar: their rest volume is round-off, of either sign, and says
  // nothing. They count as flat at rest, as the tets with a repeated corner are.
  for (int h = 0; h < mesh.numHexes(); ++h) {
    const auto first = rest_.begin() + numTets_ + static_cast<std::ptrdiff_t>(h) * perHex_;
    double largest = 0.0;
    for (auto v = first; v != first + perHex_; ++v) largest = std::max(largest, std::abs(*v));
    for (auto v = first; v != first + perHex_; ++v)
      if (std::abs(*v) <= 1e-10 * largest) *v = 0.0;
  }
}

std::vector<CorruptElement> CorruptElementCheck::find(const Eigen::Ref<const Eigen::Matrix3Xd>& x,
                                                      double minVolumeRatio) const {
  std::vector<CorruptElement> corrupt;
  for (std::size_t k = 0; k < tets_.size(); ++k) {
    if (rest_[k] == 0.0) continue;  // flat at rest: nothing to compare with
    const double ratio = signedTetVolume(x, tets_[k]) / rest_[k];
    if (ratio > minVolumeRatio) continue;
    const int i = static_cast<int>(k);
    CorruptElement c;
    c.hex = i >= numTets_;
    c.index = c.hex ? (i - numTets_) / perHex_ : i;
    c.subTet = c.hex ? firstSubTet_ + (i - numTets_) % perHex_ : -1;
    c.reason = ratio < 0.0 ? CorruptReason::kInverted : CorruptReason::kFlat;
    c.volumeRatio = ratio;
    // One entry per element, with its worst tet (a hex's tets are consecutive).
    if (!corrupt.empty() && corrupt.back().hex == c.hex && corrupt.back().index == c.index) {
      if (ratio < corrupt.back().volumeRatio) corrupt.back() = c;
    } else {
      corrupt.push_back(c);
    }
  }
  return corrupt;
}

std::vector<CorruptElement> corruptElements(const Mesh& mesh,
                                            const Eigen::Ref<const Eigen::Matrix3Xd>& x,
                                            double minVolumeRatio, HexSplit split) {
  return CorruptElementCheck(mesh, split).find(x, minVolumeRatio);
}

FaceArea hexFaceArea(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Hex& h, int face) {
  const int* f = Hex8::faces[face];
  const Eigen::Vector3d p[4] = {x.col(h[f[0]]), x.col(h[f[1]]), x.col(h[f[2]]), x.col(h[f[3]])};
  // The triangles of diagonal a-c: (a, b, c), (a, c, d); of diagonal b-d: (a, b, d), (b, c, d).
  static constexpr int kTriangles[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 1, 3}, {1, 2, 3}};
  FaceArea out;
  Eigen::Vector3d normalSum = Eigen::Vector3d::Zero();
  for (const auto& t : kTriangles) {
    const Eigen::Vector3d twiceArea = (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]);
    const double norm = twiceArea.norm();
    out.area += 0.25 * norm;  // half of each triangulation's sum, each triangle half the cross
    if (norm > 0.0) normalSum += twiceArea / norm;
  }
  if (normalSum.norm() > 0.0) out.normal = normalSum.normalized();
  return out;
}

double hexVolumeFromTets(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Hex& h, bool sixTets) {
  double volume = 0.0;
  if (sixTets)
    for (const auto& local : Hex8::sixTets) volume += signedTetVolume(x, subTet(h, local));
  else
    for (const auto& local : Hex8::fiveTets) volume += signedTetVolume(x, subTet(h, local));
  return volume;
}

}  // namespace tt
