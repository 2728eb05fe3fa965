#pragma once
// The anisotropy axes of the Adamss mass-spring system (thesis chapter "Adamss: Advanced
// Anisotropic Mass-Spring System", Secs. 2.3.1.1-2.3.1.2 and 2.4.1): three axes at the
// barycentre of every volume element (columns of the element's frame B: fibre, sheet,
// sheet-normal), each meeting the element's boundary in two intersection points. The forces of
// the Adamss models act at these points and reach the nodes through the coefficient matrix C.
//
// Point numbering (0-based): axis l = 0, 1, 2 owns q_2l, where the ray from the barycentre
// along +axis leaves the element, and q_2l+1, where the ray along -axis does, so that
// zeta_l = x_2l - x_2l+1 (Eq. 2.5) points along +axis. (The printed Eqs. 2.29 and 2.73 count the
// points q_0..q_5 with axes l = 1..3; with l 1-based axis l owns q_2l-2 and q_2l-1.)
//
// Ray casting (Eqs. 2.8-2.16 for hexahedra, 2.20-2.24 for tetrahedra): the ray x_b + d s u
// (Eq. 2.9 with the unit axis u, s = +1 or -1) is followed to the first face it crosses.
//   Tetrahedra: along the ray the barycentric coordinates are lambda(d) = 1/4 + d s G^T u (G the
//   gradients of the linear shape functions), and the ray leaves through the face opposite the
//   node whose coordinate first reaches zero. The coordinates there are the area coordinates
//   of the point in that face, the weights of Eqs. 2.21 and 2.24.
//   Hexahedra: a face is the bilinear patch x(xi, eta) = sum_i N_i(xi, eta) x_i of Eq. 2.7 over
//   its four nodes (in Hex8::faces order: N_1 at (0, 0), N_2 at (1, 0), N_3 at (1, 1), N_4 at
//   (0, 1)); x(xi, eta) = x_b + d s u is solved by Newton's method from the face centre, and
//   the face with the smallest d > 0 and (xi, eta) in [0, 1]^2 is the one the ray leaves
//   through. For a rectangular face this is the intersection with its plane (Eqs. 2.10-2.12,
//   dividing by u . n with the unit axis, as the ray of Eq. 2.9 is written) with the
//   coefficients of Eq. 2.16 (xi = 2 S_j14 / S, eta = 2 S_j12 / S, S = |x1 - x2| |x1 - x4|, in
//   the node numbering of Eq. 2.7); for a non-planar face it is the point on the bilinear
//   patch through which the positions of Eq. 2.6 interpolate.
//
// The coefficient matrix C (Eq. 2.17) has one row per element node and one column per point:
// column j holds the weights of q_j on the nodes of its face (3 non-zeros in a tet, 4 in a
// hex), summing to 1. Points and their velocities follow the nodes, x_j = sum_i C_ij x_i
// (Eqs. 2.25-2.27), and point forces go to the nodes by f_i = sum_j C_ij f_j (Eq. 2.29): the
// transpose of the same map, so the point forces and the nodal forces do the same work and have
// the same resultant and moment.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <vector>

#include "tissue_trainer/core/element/element.h"
#include "tissue_trainer/core/element/hex8.h"
#include "tissue_trainer/core/element/tet4.h"
#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {
namespace adamss {

constexpr int kAxes = 3;
constexpr int kAxisPoints = 2 * kAxes;

// Positions, velocities or forces of the six intersection points, one column per point.
using PointMatrix = Eigen::Matrix<double, 3, kAxisPoints>;
// The coefficient matrix C of an element with N nodes (Eq. 2.17).
template <int N>
using PointCoefficients = Eigen::Matrix<double, N, kAxisPoints>;

// What an element's axes need at rest, computed once.
template <class Element>
struct AxisRest {
  PointCoefficients<Element::kNodes> C = PointCoefficients<Element::kNodes>::Zero();
  // The face (index into Element::faces) holding each point.
  std::array<int, kAxisPoints> face{};
  // The rest axis lengths |zeta_l^0| = |x_2l - x_2l+1| (Eq. 2.30).
  Eigen::Vector3d length0 = Eigen::Vector3d::Zero();
  // The unit rest axes (columns), zeta_l^0 = length0[l] * axes0.col(l).
  Eigen::Matrix3d axes0 = Eigen::Matrix3d::Identity();
};

// The axes' rest data of one element from its rest node positions Xe (columns in the element's
// node order) and its axis directions (columns; normalised here, need not be orthogonal).
// Returns false, leaving `out` unspecified, when the element is flat or an axis is zero or not
// finite (a ray then meets no face).
bool tetAxisRest(const NodeMatrix<Tet4::kNodes>& Xe, const Eigen::Matrix3d& axes,
                 AxisRest<Tet4>& out);
bool hexAxisRest(const NodeMatrix<Hex8::kNodes>& Xe, const Eigen::Matrix3d& axes,
                 AxisRest<Hex8>& out);

// Positions (or velocities) of the intersection points from the element's node positions (or
// velocities), Eqs. 2.26-2.27.
template <int N>
PointMatrix intersectionPoints(const NodeMatrix<N>& xe, const PointCoefficients<N>& C) {
  return xe * C;
}

// Nodal forces of point forces fq (Eq. 2.29).
template <int N>
NodeMatrix<N> distributeToNodes(const PointMatrix& fq, const PointCoefficients<N>& C) {
  return fq * C.transpose();
}

// The current axes zeta_l = x_2l - x_2l+1 (Eq. 2.5) as columns.
inline Eigen::Matrix3d axisVectors(const PointMatrix& xq) {
  Eigen::Matrix3d zeta;
  for (int l = 0; l < kAxes; ++l) zeta.col(l) = xq.col(2 * l) - xq.col(2 * l + 1);
  return zeta;
}

// Per axis l, the mean over its two points q_2l, q_2l+1 of |a_j . u_l|: the vector area a_j of
// the face holding the point (hex faces: half the cross product of the diagonals, the mean of
// the face's two triangulations) projected on the unit axis u_l, at the positions xe. The area
// the area-scaled springs multiply a stiffness in Pa by (Eqs. 2.38 and 2.55).
Eigen::Vector3d projectedFaceAreas(const NodeMatrix<Tet4::kNodes>& xe, const AxisRest<Tet4>& rest);
Eigen::Vector3d projectedFaceAreas(const NodeMatrix<Hex8::kNodes>& xe, const AxisRest<Hex8>& rest);

// The axes of every element of a mesh, in mesh order, with the axis directions taken from the
// elements' fibre frames (Mesh::fibreFrame, Mesh::hexFibreFrame).
struct AxisMesh {
  std::vector<Tet> tets;
  std::vector<AxisRest<Tet4>> tetRest;
  std::vector<Hex> hexes;
  std::vector<AxisRest<Hex8>> hexRest;
};

// Throws std::invalid_argument naming the element ("tet 12", "hex 3") whose rays meet no face.
AxisMesh buildAxes(const Mesh& mesh);

// What the spring models (axial_springs.h, torsion_springs.h) keep of an element's axes: the
// current axes are zeta = x_e D (D_pl = C_p,2l - C_p,2l+1), and a force g_l at q_2l with -g_l at
// q_2l+1 reaches node p as D_pl g_l (Eq. 2.29).
template <int N>
struct AxisSpringRest {
  Eigen::Matrix<double, N, kAxes> D = Eigen::Matrix<double, N, kAxes>::Zero();
  Eigen::Vector3d length0 = Eigen::Vector3d::Zero();  // |zeta_l^0|
  Eigen::Vector3d area = Eigen::Vector3d::Zero();     // projectedFaceAreas at rest
  Eigen::Vector3d restCosine = Eigen::Vector3d::Zero();  // of the pairs (0, 1), (0, 2), (1, 2)
  double volume = 0.0;                                // V0
  // det[zeta_0^0 zeta_1^0 zeta_2^0]: the signed rest volume V_h^0 of the virtual hexahedron.
  double axisVolume = 0.0;
};

template <class Element>
AxisSpringRest<Element::kNodes> axisSpringRest(const NodeMatrix<Element::kNodes>& Xe,
                                               const AxisRest<Element>& axes, double volume) {
  AxisSpringRest<Element::kNodes> r;
  for (int l = 0; l < kAxes; ++l) r.D.col(l) = axes.C.col(2 * l) - axes.C.col(2 * l + 1);
  r.length0 = axes.length0;
  r.area = projectedFaceAreas(Xe, axes);
  r.restCosine << axes.axes0.col(0).dot(axes.axes0.col(1)), axes.axes0.col(0).dot(axes.axes0.col(2)),
      axes.axes0.col(1).dot(axes.axes0.col(2));
  r.volume = volume;
  r.axisVolume = axes.length0.prod() * axes.axes0.col(0).dot(axes.axes0.col(1).cross(axes.axes0.col(2)));
  return r;
}

}  // namespace adamss
}  // namespace tt
