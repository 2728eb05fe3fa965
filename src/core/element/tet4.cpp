#include "tissue_trainer/core/element/tet4.h"

#include <Eigen/LU>

namespace tt {

Tet4::Rest Tet4::rest(const Eigen::Matrix3Xd& X, const Nodes& nodes) {
  Eigen::Matrix3d Dm;
  Dm << X.col(nodes[1]) - X.col(nodes[0]), X.col(nodes[2]) - X.col(nodes[0]),
      X.col(nodes[3]) - X.col(nodes[0]);
  Rest r;
  r.volume = Dm.determinant() / 6.0;
  // Rows of Dm^-1 are the gradients of the barycentric coordinates 1..3.
  const Eigen::Matrix3d DmInvT = Dm.inverse().transpose();
  r.grad[0].rightCols<3>() = DmInvT;
  r.grad[0].col(0) = -DmInvT.rowwise().sum();
  r.weight[0] = r.volume;
  return r;
}

}  // namespace tt
