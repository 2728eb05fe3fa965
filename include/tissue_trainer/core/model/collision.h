#pragma once
// The force model `collision`: penalty forces pushing nodes out of rigid collision bodies
// (planes, spheres and closed triangle meshes), after M. Bao, "Derivation of Quasistatics and
// Landmark Optimization for Muscles", Sec. 5.7: "a force of some strength eps that pushes a
// particle back towards the surface ... further scaled by the depth of the particle inside the
// collision body". The paper leaves the details open; here, for a node x inside a body with
// c(x) the nearest point of the body's surface and d = |c - x| its depth,
//   f = eps (c - x) = eps d n,   E = eps d^2 / 2,   df/dx = eps (dc/dx - I),
// n the outward normal at c. dc/dx is the projector onto the feature holding c: I - n n^T on a
// plane or a triangle's face, t t^T on an edge with direction t, 0 at a vertex, and
// (R / r)(I - n n^T) on a sphere of radius R at distance r from its centre. The force is zero
// outside and on the surface, and continuous (E is C1) across it. Only the sphere's stiffness
// has a positive part (its tangential R/r - 1 > 0); psd_projection replaces it by I - n n^T.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/model/force_model.h"

namespace tt {

// Where a point inside a body is pushed: the nearest surface point and its Jacobian dc/dx.
struct Penetration {
  Eigen::Vector3d point;
  Eigen::Matrix3d pointJacobian;
};

// A closed, consistently oriented triangle surface with a bounding-volume tree, for the nearest
// point and the inside test (the sign of (x - c) . N with N the angle-weighted pseudo-normal
// of the nearest feature: "Signed distance computation using the angle weighted pseudonormal",
// 2005). Queries allocate nothing.
class ClosedSurface {
 public:
  // Throws std::invalid_argument when an edge does not have exactly two triangles traversing
  // it in opposite directions (an open, non-manifold or inconsistently oriented surface), or a
  // triangle has no area. An inward orientation (negative enclosed volume) is turned outward.
  ClosedSurface(Eigen::Matrix3Xd vertices, std::vector<Triangle> triangles);

  // True when x is strictly inside; then `out` is filled.
  bool inside(const Eigen::Vector3d& x, Penetration& out) const;
  // The nearest surface point (any side) and the signed distance (negative inside).
  double signedDistance(const Eigen::Vector3d& x, Eigen::Vector3d& nearest) const;

  int numTriangles() const { return static_cast<int>(triangles_.size()); }

 private:
  struct Node {
    Eigen::Vector3d lo, hi;
    int left = -1, right = -1;  // children, or -1 at a leaf
    int first = 0, count = 0;   // a leaf's range in order_
  };
  enum Feature { kFace, kEdge0, kEdge1, kEdge2, kVertex0, kVertex1, kVertex2 };
  struct Nearest {
    Eigen::Vector3d point;
    double distance2;
    int triangle;
    Feature feature;
  };

  int build(int first, int count);
  Nearest nearest(const Eigen::Vector3d& x) const;
  Nearest nearestOnTriangle(const Eigen::Vector3d& x, int t) const;
  Eigen::Vector3d pseudoNormal(const Nearest& n) const;

  Eigen::Matrix3Xd vertices_;
  std::vector<Triangle> triangles_;
  std::vector<Eigen::Vector3d> faceNormals_;    // unit
  std::vector<Eigen::Vector3d> edgeNormals_;    // per triangle edge k (v_k, v_k+1): sum of its faces' normals
  std::vector<Eigen::Vector3d> vertexNormals_;  // angle-weighted
  std::vector<int> order_;                      // triangles in tree order
  std::vector<Node> nodes_;
  Eigen::Vector3d lo_, hi_;                     // bounding box
};

struct CollisionBody {
  enum class Kind { kPlane, kSphere, kMesh };
  Kind kind = Kind::kPlane;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // plane point or sphere centre
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(); // plane: unit, pointing out of the body
  double radius = 0.0;                               // sphere
  int surface = -1;                                  // mesh: index into the model's surfaces

  static CollisionBody plane(const Eigen::Vector3d& point, const Eigen::Vector3d& normal);
  static CollisionBody sphere(const Eigen::Vector3d& centre, double radius);
};

class CollisionModel final : public ForceModel {
 public:
  // `nodes`: the nodes tested; `stiffness` eps (N/m) > 0. Throws std::invalid_argument for a
  // stiffness <= 0, a node outside [0, numNodes), a zero plane normal, a radius <= 0 or a
  // mesh body without its surface.
  CollisionModel(int numNodes, std::vector<int> nodes, double stiffness,
                 std::vector<CollisionBody> bodies, std::vector<ClosedSurface> surfaces,
                 bool psdProjection);

  const char* name() const override { return "collision"; }
  bool toleratesInversion() const override { return true; }  // no elements

  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;

  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;
  bool hasStiffnessProduct() const override { return true; }
  void addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double scale,
                         Eigen::VectorXd& out) const override;

  // True when x is inside body b; then `out` is filled.
  bool penetration(const CollisionBody& b, const Eigen::Vector3d& x, Penetration& out) const;

 private:
  // Calls visit(node, penetration) for every tested node inside a body (once per body).
  template <class Visit>
  void forEachContact(const Eigen::VectorXd& x, const Visit& visit) const;

  std::vector<int> nodes_;
  double stiffness_;
  std::vector<CollisionBody> bodies_;
  std::vector<ClosedSurface> surfaces_;
  bool psdProjection_;
};

}  // namespace tt
