#include "tissue_trainer/core/element/point_stiffness.h"

namespace tt {
namespace {

// G(g)(i + 3 j, 3 p + i) = g(j, p): vec(dx g^T) = G(g) vec(dx).
template <int N>
Eigen::Matrix<double, 9, 3 * N> vectorisedGradient(const NodeMatrix<N>& g) {
  Eigen::Matrix<double, 9, 3 * N> G = Eigen::Matrix<double, 9, 3 * N>::Zero();
  for (int p = 0; p < N; ++p)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) G(i + 3 * j, 3 * p + i) = g(j, p);
  return G;
}

}  // namespace

template <int N>
void subtractPointStiffness(const Eigen::Matrix<double, 9, 9>& A, const NodeMatrix<N>& left,
                            const NodeMatrix<N>& right, double weight,
                            Eigen::Matrix<double, 3 * N, 3 * N>& K) {
  const Eigen::Matrix<double, 9, 3 * N> Gright = vectorisedGradient<N>(right);
  if (&left == &right) {
    K.noalias() -= weight * (Gright.transpose() * A * Gright);
    return;
  }
  K.noalias() -= weight * (vectorisedGradient<N>(left).transpose() * A * Gright);
}

template void subtractPointStiffness<4>(const Eigen::Matrix<double, 9, 9>&, const NodeMatrix<4>&,
                                        const NodeMatrix<4>&, double,
                                        Eigen::Matrix<double, 12, 12>&);
template void subtractPointStiffness<8>(const Eigen::Matrix<double, 9, 9>&, const NodeMatrix<8>&,
                                        const NodeMatrix<8>&, double,
                                        Eigen::Matrix<double, 24, 24>&);

}  // namespace tt
