#pragma once
// The finite-volume form of a tet's elastic forces, M. Bao, "Derivation of Quasistatics and
// Landmark Optimization for Muscles", Sec. 4.4 (after Teran, Blemker, Ng Thow Hing and Fedkiw
// 2003): the force on node i is g_i = P b_i, with b_i = -(1/3) (A_1 N_1 + A_2 N_2 + A_3 N_3) the
// area-weighted outward normals of the three rest faces touching node i. The four normals sum
// to zero, so b_i = (1/3) A N of the face opposite node i. In matrix form B_m = [b_1 b_2 b_3] =
// -V Dm^-T with V = |det Dm| / 6, i.e. Dm^T B_m = -V I (the paper prints +V I, then argues the
// negative volume), and g_0 = -(g_1 + g_2 + g_3). This is the element form f = -V P Dm^-T of
// tet4.h, from the faces instead of the shape-function gradients.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

namespace tt {

struct Tet4FiniteVolume {
  using Nodes = Eigen::Matrix<double, 3, 4>;  // rest positions, one column per node

  // A_k N_k of the rest face opposite node k, outward (either orientation of the tet).
  static Nodes areaWeightedNormals(const Nodes& X) {
    Nodes normals;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d a = X.col((k + 1) % 4), b = X.col((k + 2) % 4),
                            c = X.col((k + 3) % 4);
      Eigen::Vector3d n = 0.5 * (b - a).cross(c - a);
      if (n.dot(X.col(k) - a) > 0.0) n = -n;  // away from the opposite node
      normals.col(k) = n;
    }
    return normals;
  }

  // b_i = -(1/3) (sum of A_k N_k over the faces touching node i, k != i).
  static Nodes nodeVectors(const Nodes& X) {
    const Nodes normals = areaWeightedNormals(X);
    Nodes b;
    for (int i = 0; i < 4; ++i)
      b.col(i) = -(normals.rowwise().sum() - normals.col(i)) / 3.0;
    return b;
  }

  // B_m = -V Dm^-T, Dm = [X1 - X0, X2 - X0, X3 - X0].
  static Eigen::Matrix3d Bm(const Nodes& X) {
    const Eigen::Matrix3d Dm = X.rightCols<3>().colwise() - X.col(0);
    return -std::abs(Dm.determinant()) / 6.0 * Dm.inverse().transpose();
  }

  // Node forces g_i = P b_i of a tet with first Piola-Kirchhoff stress P.
  static Nodes forces(const Eigen::Matrix3d& P, const Nodes& X) { return P * nodeVectors(X); }
};

}  // namespace tt
