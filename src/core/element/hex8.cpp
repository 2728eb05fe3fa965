#include "tissue_trainer/core/element/hex8.h"

#include <Eigen/LU>
#include <cmath>

namespace tt {

Eigen::Matrix<double, Hex8::kNodes, 1> Hex8::shape(const Eigen::Vector3d& xi) {
  Eigen::Matrix<double, kNodes, 1> N;
  for (int p = 0; p < kNodes; ++p)
    N[p] = 0.125 * (1.0 + corner[p][0] * xi[0]) * (1.0 + corner[p][1] * xi[1]) *
           (1.0 + corner[p][2] * xi[2]);
  return N;
}

Hex8::Gradients Hex8::referenceGradients(const Eigen::Vector3d& xi) {
  Gradients dN;
  for (int p = 0; p < kNodes; ++p) {
    const double a = 1.0 + corner[p][0] * xi[0];
    const double b = 1.0 + corner[p][1] * xi[1];
    const double c = 1.0 + corner[p][2] * xi[2];
    dN.col(p) << 0.125 * corner[p][0] * b * c, 0.125 * corner[p][1] * a * c,
        0.125 * corner[p][2] * a * b;
  }
  return dN;
}

Eigen::Vector3d Hex8::gaussPoint(int q) {
  const double g = 1.0 / std::sqrt(3.0);
  return {g * corner[q][0], g * corner[q][1], g * corner[q][2]};
}

Hex8::Gradients Hex8::gradientsAt(const NodeMatrix<kNodes>& Xe, const Eigen::Vector3d& xi,
                                  double* detJ) {
  const Gradients dN = referenceGradients(xi);
  const Eigen::Matrix3d J = Xe * dN.transpose();  // J(i, k) = dX_i / dxi_k
  if (detJ) *detJ = J.determinant();
  // grad_X N_p = J^-T dN_p/dxi.
  return J.inverse().transpose() * dN;
}

Hex8::Rest Hex8::rest(const Eigen::Matrix3Xd& X, const Nodes& nodes) {
  const NodeMatrix<kNodes> Xe = gatherNodes<kNodes>(X, nodes);
  Rest r;
  for (int q = 0; q < kPoints; ++q) {
    double detJ = 0.0;
    r.grad[q] = gradientsAt(Xe, gaussPoint(q), &detJ);
    r.weight[q] = detJ;  // the 2-point Gauss weights are 1 in each direction
    r.volume += detJ;
  }
  return r;
}

}  // namespace tt
