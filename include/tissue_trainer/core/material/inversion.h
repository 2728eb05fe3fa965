#pragma once
// The rotation-only SVD of inversion handling (Irving, Teran and Fedkiw 2004, Sec. 4):
// F = U diag(sigma) V^T with det U = det V = +1, the sign of det F carried by the smallest
// singular value, and the clamped gradient F^ = U diag(max(sigma_i, threshold)) V^T.
#include <Eigen/Core>

namespace tt {

struct RotationSvd {
  Eigen::Matrix3d U, V;   // rotations
  Eigen::Vector3d sigma;  // sigma(0) >= sigma(1) >= |sigma(2)|; sigma(2) < 0 when det F < 0
};

RotationSvd rotationSvd(const Eigen::Matrix3d& F);

// F^ for `threshold` > 0; `clamped` tells whether any singular value was raised.
Eigen::Matrix3d clampedGradient(const RotationSvd& svd, double threshold, bool& clamped);

}  // namespace tt
