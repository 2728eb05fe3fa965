#pragma once
// The stiffness one point of an element adds, the same for every law: with a law's tangent
// A = d vec(P) / d vec(F) (9 x 9, column-major vec) at the point,
//   K -= weight * G(left)^T A G(right),
// where G(g) is the 9 x 3N matrix with vec(dx g^T) = G(g) vec(dx) for node displacements dx
// (3 x N, one column a node): right maps the displacements to dF, left the stress change to
// node forces. The element models over a law call it at each point; it is compiled once for
// tetrahedra (N = 4) and hexahedra (N = 8) in src/core/element/point_stiffness.cpp rather than
// once per law, where these 12 x 12 and 24 x 24 products were most of each law's compile time.
#include <Eigen/Core>

#include "tissue_trainer/core/element/element.h"

namespace tt {

template <int N>
void subtractPointStiffness(const Eigen::Matrix<double, 9, 9>& A, const NodeMatrix<N>& left,
                            const NodeMatrix<N>& right, double weight,
                            Eigen::Matrix<double, 3 * N, 3 * N>& K);

extern template void subtractPointStiffness<4>(const Eigen::Matrix<double, 9, 9>&,
                                               const NodeMatrix<4>&, const NodeMatrix<4>&,
                                               double, Eigen::Matrix<double, 12, 12>&);
extern template void subtractPointStiffness<8>(const Eigen::Matrix<double, 9, 9>&,
                                               const NodeMatrix<8>&, const NodeMatrix<8>&,
                                               double, Eigen::Matrix<double, 24, 24>&);

}  // namespace tt
