#pragma once
// Rest-configuration constants of a tetrahedron, shared by the tet force models and the mesh
// writers: rest volume V0 = det(Dm)/6 and the gradients g_p = grad_X Lambda_p of the
// barycentric coordinates. F = sum_p x_p g_p^T.
#include <Eigen/Core>
#include <Eigen/LU>

#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

struct TetRest {
  double volume = 0.0;        // V0 > 0 for a positively oriented tet
  Eigen::Matrix<double, 3, 4> grad;  // column p is g_p; the columns sum to zero
};

inline TetRest tetRest(const Eigen::Ref<const Eigen::Matrix3Xd>& rest, const Tet& t) {
  Eigen::Matrix3d Dm;
  Dm << rest.col(t[1]) - rest.col(t[0]), rest.col(t[2]) - rest.col(t[0]),
      rest.col(t[3]) - rest.col(t[0]);
  TetRest r;
  r.volume = Dm.determinant() / 6.0;
  const Eigen::Matrix3d DmInvT = Dm.inverse().transpose();  // rows of Dm^-1 are g_1..g_3
  r.grad.rightCols<3>() = DmInvT;
  r.grad.col(0) = -DmInvT.rowwise().sum();
  return r;
}

// Deformation gradient F = sum_p x_p g_p^T of tet t at positions x (3n vector).
inline Eigen::Matrix3d deformationGradient(const Eigen::VectorXd& x, const Tet& t,
                                           const TetRest& r) {
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
  for (int p = 0; p < 4; ++p) F.noalias() += x.segment<3>(3 * t[p]) * r.grad.col(p).transpose();
  return F;
}

}  // namespace tt
