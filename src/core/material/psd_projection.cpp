#include "tissue_trainer/core/material/psd_projection.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace tt {

namespace {

template <int N>
Eigen::Matrix<double, N, N> clampEigenvalues(const Eigen::Matrix<double, N, N>& A) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(0.5 * (A + A.transpose()));
  const Eigen::Matrix<double, N, 1> lambda = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

// The 2 x 2 case in closed form (the eigen solver's instantiation for it cost 4.6 s of
// compilation): with eigenvalues l1 >= l2 of the symmetric part B, (B - l2 I) / (l1 - l2)
// projects onto l1's eigenvector, so the clamped matrix is B when l2 >= 0, zero when l1 <= 0
// and l1 (B - l2 I) / (l1 - l2) otherwise.
Eigen::Matrix2d clampEigenvalues2(const Eigen::Matrix2d& A) {
  const Eigen::Matrix2d B = 0.5 * (A + A.transpose());
  const double mean = 0.5 * (B(0, 0) + B(1, 1));
  const double radius = std::hypot(0.5 * (B(0, 0) - B(1, 1)), B(0, 1));
  const double l1 = mean + radius, l2 = mean - radius;
  if (l2 >= 0.0) return B;
  if (l1 <= 0.0) return Eigen::Matrix2d::Zero();
  return (l1 / (l1 - l2)) * (B - l2 * Eigen::Matrix2d::Identity());
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
    B = clampEigenvalues2(B);
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) out(pair[a], pair[b]) = B(a, b);
  }
  Ahat = out;
}

}  // namespace tt
