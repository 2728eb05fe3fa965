#pragma once
// A render surface embedded in a tet mesh: every surface vertex is tied to one tet by fixed
// barycentric weights, so the deformed vertex is the same affine combination of that tet's
// deformed nodes. Finding the tets uses a uniform grid of buckets over tet bounding boxes.
#include <Eigen/Core>
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

// What to do with a point that no tet contains: it is tied to the nearest tet (Euclidean
// distance to the solid tet) and either
//   kClamp: to the closest point of that tet (weights in [0,1]; the vertex snaps onto the
//           mesh boundary, moving it by up to maxOutsideDistance at rest), or
//   kExtrapolate: to the point itself (weights may be slightly negative; the rest surface is
//           reproduced exactly and the vertex follows the nearest tet's affine motion).
enum class OutsidePolicy { kClamp, kExtrapolate };

class Embedding {
 public:
  Embedding() = default;
  // points: 3 x V rest positions of the surface vertices, in the mesh's units and frame.
  Embedding(const Mesh& mesh, const Eigen::Matrix3Xd& points,
            OutsidePolicy policy = OutsidePolicy::kClamp);

  // Deformed vertices (3 x V) from deformed node positions x (3n, node-major xyz).
  void apply(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Matrix3Xd& out) const;
  Eigen::Matrix3Xd apply(const Eigen::Ref<const Eigen::VectorXd>& x) const;

  int numPoints() const { return static_cast<int>(tet_.size()); }
  int tetOf(int point) const { return tet_[point]; }
  // Barycentric weights of node p (0..3) of tetOf(point); they sum to 1.
  const Eigen::Vector4d& weights(int point) const { return weights_[point]; }

  // Points no tet contains (within a relative tolerance), and the largest distance from such
  // a point to its tet.
  int numOutside() const { return numOutside_; }
  double maxOutsideDistance() const { return maxOutsideDistance_; }
  // Barycentric or distance evaluations made by the search, per point (a brute-force search
  // would make numTets per point).
  double meanTetsTested() const {
    return numPoints() ? static_cast<double>(tetsTested_) / numPoints() : 0.0;
  }

 private:
  std::vector<Tet> nodes_;  // the four nodes of each point's tet
  std::vector<int> tet_;
  std::vector<Eigen::Vector4d> weights_;
  int numOutside_ = 0;
  double maxOutsideDistance_ = 0.0;
  long tetsTested_ = 0;
};

// Barycentric coordinates of p in tet (a, b, c, d), and the closest point of the solid tet to
// p with its distance. Exposed for tests and for picking.
Eigen::Vector4d barycentric(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c, const Eigen::Vector3d& d,
                            const Eigen::Vector3d& p);
// Returns the squared distance from p to the solid tet; `closest` gets the barycentric
// coordinates (all >= 0, sum 1) of the closest point.
double closestPointInTet(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& c, const Eigen::Vector3d& d,
                         const Eigen::Vector3d& p, Eigen::Vector4d& closest);

}  // namespace tt
