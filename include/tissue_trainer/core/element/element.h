#pragma once
// What the element types share: an element's node positions gathered into a 3 x N matrix
// (one column per element node) and the deformation gradient F = sum_p x_p (grad_X N_p)^T
// at one point from those positions and the shape-function gradients at that point.
//
// An element type E (Tet4, Hex8) provides
//   E::kNodes, E::kPoints          nodes and quadrature points per element
//   E::Nodes                       std::array<int, kNodes> of global node indices
//   E::Gradients                   3 x kNodes: column p is grad_X N_p at one point
//   E::Rest                        volume, grad[q] and weight[q] (quadrature weight * det J,
//                                  summing to the volume) for q < kPoints
//   E::rest(X, nodes)              the rest data from rest positions X (3 x n)
//   E::kFaces, E::kFaceNodes,      the boundary faces in local node numbers, counter-clockwise
//   E::faces                       seen from outside a positively oriented element
// so that a force model over E integrates an energy density psi(F) as
//   sum_q weight[q] * psi(deformationGradient(gatherNodes<E::kNodes>(x, nodes), grad[q])).
// Everything is fixed-size: no allocation.
#include <Eigen/Core>
#include <array>

namespace tt {

template <int N>
using NodeMatrix = Eigen::Matrix<double, 3, N>;

// Columns x_p of the element's nodes from a 3n vector of positions.
template <int N>
NodeMatrix<N> gatherNodes(const Eigen::VectorXd& x, const std::array<int, N>& nodes) {
  NodeMatrix<N> xe;
  for (int p = 0; p < N; ++p) xe.col(p) = x.template segment<3>(3 * nodes[p]);
  return xe;
}

// Columns x_p of the element's nodes from a 3 x n matrix of positions.
template <int N>
NodeMatrix<N> gatherNodes(const Eigen::Matrix3Xd& x, const std::array<int, N>& nodes) {
  NodeMatrix<N> xe;
  for (int p = 0; p < N; ++p) xe.col(p) = x.col(nodes[p]);
  return xe;
}

// F = sum_p x_p g_p^T for node positions xe and gradients g_p = grad.col(p) at one point.
template <int N>
Eigen::Matrix3d deformationGradient(const NodeMatrix<N>& xe, const NodeMatrix<N>& grad) {
  return xe * grad.transpose();
}

}  // namespace tt
