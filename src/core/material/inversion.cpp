#include "tissue_trainer/core/material/inversion.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>

namespace tt {

RotationSvd rotationSvd(const Eigen::Matrix3d& F) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  RotationSvd r{svd.matrixU(), svd.matrixV(), svd.singularValues()};
  // Eigen sorts the singular values in decreasing order: a reflection is moved onto the last.
  if (r.U.determinant() < 0.0) {
    r.U.col(2) *= -1.0;
    r.sigma(2) *= -1.0;
  }
  if (r.V.determinant() < 0.0) {
    r.V.col(2) *= -1.0;
    r.sigma(2) *= -1.0;
  }
  return r;
}

Eigen::Matrix3d clampedGradient(const RotationSvd& svd, double threshold, bool& clamped) {
  Eigen::Vector3d s = svd.sigma;
  clamped = false;
  for (int i = 0; i < 3; ++i) {
    if (s(i) < threshold) {
      s(i) = threshold;
      clamped = true;
    }
  }
  return svd.U * s.asDiagonal() * svd.V.transpose();
}

}  // namespace tt
