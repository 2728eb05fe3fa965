#pragma once
// Positive semi-definite projection of a law's tangent dP/dF (law.h's 9 x 9 convention).
//   projectPsd: any law; the symmetric part's negative eigenvalues set to zero.
//   isotropicProjectedTangent: an isotropic law, in the frame of its singular values (Teran,
//   Sifakis, Irving and Fedkiw, "Robust quasistatic finite elements and flesh simulation",
//   2005, Sec. 5): there the tangent splits into the 3 x 3 block of the diagonal entries and
//   three 2 x 2 blocks of the pairs (F_ij, F_ji); each block is clamped on its own and the
//   result turned back with U and V. Same answer as projectPsd, from small blocks.
// teran_muscle's diagonalBlocksTangent (LawOptions::psdMethod kDiagonalBlocks) uses the same
// blocks for its isotropic part and adds its fibre term projected on its own.
#include <Eigen/Core>

#include "tissue_trainer/core/material/inversion.h"
#include "tissue_trainer/core/material/law.h"

namespace tt {

void projectPsd(Matrix9d& A);

// The 9 x 9 rotation vec(dF^) -> vec(U dF^ V^T).
Matrix9d frameRotation(const Eigen::Matrix3d& U, const Eigen::Matrix3d& V);

// Clamps the blocks of a tangent given in the singular-value frame (entries outside the
// blocks, zero for an isotropic law, are dropped).
void projectDiagonalFrameBlocks(Matrix9d& Ahat);

// The projected tangent of isotropic law L at U diag(sigma) V^T.
template <class Law>
Matrix9d isotropicProjectedTangent(const typename Law::Parameters& p, const RotationSvd& svd,
                                   const Eigen::Vector3d& sigma) {
  Matrix9d Ahat = lawTangent<Law>(p, Eigen::Matrix3d(sigma.asDiagonal()));
  projectDiagonalFrameBlocks(Ahat);
  const Matrix9d R = frameRotation(svd.U, svd.V);
  return R * Ahat * R.transpose();
}

}  // namespace tt
