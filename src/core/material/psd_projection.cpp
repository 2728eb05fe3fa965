#include "tissue_trainer/core/material/psd_projection.h"

#include <Eigen/Eigenvalues>

namespace tt {

namespace {

template <int N>
Eigen::Matrix<double, N, N> clampEigenvalues(const Eigen::Matrix<double, N, N>& A) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(0.5 * (A + A.transpose()));
  const Eigen::Matrix<double, N, 1> lambda = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

// vec indices (i + 3 j) of the diagonal entries and of the off-diagonal pairs (F_ij, F_ji).
constexpr int kDiagonal[3] = {0, 4, 8};
constexpr int kPairs[3][2] = {{3, 1}, {6, 2}, {7, 5}};

}  // namespace

void projectPsd(Matrix9d& A) { A = clampEigenvalues<9>(A); }

Matrix9d frameRotation(const Eigen::Matrix3d& U, const Eigen::Matrix3d& V) {
  Matrix9d R;
  for (int l = 0; l < 3; ++l)
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) R(i + 3 * j, k + 3 * l) = U(i, k) * V(j, l);
  return R;
}

void projectDiagonalFrameBlocks(Matrix9d& Ahat) {
  Eigen::Matrix3d D;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) D(a, b) = Ahat(kDiagonal[a], kDiagonal[b]);
  Matrix9d out = Matrix9d::Zero();
  D = clampEigenvalues<3>(D);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) out(kDiagonal[a], kDiagonal[b]) = D(a, b);
  for (const auto& pair : kPairs) {
    Eigen::Matrix2d B;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) B(a, b) = Ahat(pair[a], pair[b]);
    B = clampEigenvalues<2>(B);
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) out(pair[a], pair[b]) = B(a, b);
  }
  Ahat = out;
}

}  // namespace tt
