#pragma once
// One law evaluated at one quadrature point with the options of law.h: the gradient the law
// sees (F, or the clamped F^ of inversion handling) and the tangent (projected or not).
//
// With inversion handling the stress and energy are the law's at F^, which is F itself until
// a singular value falls below the threshold. Below it, the stress is the law's stress at F^
// (Irving, Teran and Fedkiw 2004, Sec. 4): not the gradient of an energy, so the force-energy
// and stiffness-force checks hold only where nothing is clamped, and the tangent used there
// is the law's tangent at F^.
#include <Eigen/Core>

#include "tissue_trainer/core/material/inversion.h"
#include "tissue_trainer/core/material/law.h"
#include "tissue_trainer/core/material/psd_projection.h"

namespace tt {

struct LawPoint {
  Eigen::Matrix3d F;  // where the law is evaluated
  RotationSvd svd;    // of the element's F, when hasSvd
  bool hasSvd = false;
  bool clamped = false;
};

// True when no singular value of F can be below `threshold`, from J and tr C alone: with
// C = F^T F, its eigenvalues l1 <= l2 <= l3 have l1 l2 l3 = J^2 and l2 l3 <= (tr C / 2)^2, so
// sigma_min = sqrt(l1) >= 2 J / tr C when J > 0. A margin of 1% covers the round-off of both
// sides. Most elements of a moderately deformed mesh pass, and skip the SVD.
inline bool singularValuesSurelyAbove(const Eigen::Matrix3d& F, double threshold) {
  const double J = F.determinant();
  return J > 0.0 && 2.0 * J > 1.01 * threshold * F.squaredNorm();
}

inline LawPoint lawPoint(const Eigen::Matrix3d& F, const LawOptions& options) {
  LawPoint point;
  if (options.inversionThreshold > 0.0 &&
      !singularValuesSurelyAbove(F, options.inversionThreshold)) {
    point.svd = rotationSvd(F);
    point.hasSvd = true;
    point.F = clampedGradient(point.svd, options.inversionThreshold, point.clamped);
    if (!point.clamped) point.F = F;  // bitwise the same answers as without the option
  } else {
    point.F = F;
  }
  return point;
}

// The singular values of the point's F (its SVD computed if the point has none yet), clamped
// at the inversion threshold as lawPoint clamps F.
inline Eigen::Vector3d clampedSingularValues(LawPoint& point, const LawOptions& options) {
  if (!point.hasSvd) {
    point.svd = rotationSvd(point.F);
    point.hasSvd = true;
  }
  Eigen::Vector3d sigma = point.svd.sigma;
  if (options.inversionThreshold > 0.0) sigma = sigma.cwiseMax(options.inversionThreshold);
  return sigma;
}

// The tangent used at the point: the law's, or its PSD projection (options.psdMethod; a law
// without the diagonal-blocks form is refused when its model is built, so the eigenvalue
// clamp below is reached only for kEigen).
template <class Law>
Matrix9d pointTangent(const typename Law::Parameters& p, LawPoint& point,
                      const LawOptions& options) {
  if (!options.psdProjection) return lawTangent<Law>(p, point.F);
  if constexpr (Law::kIsotropic) {
    return isotropicProjectedTangent<Law>(p, point.svd, clampedSingularValues(point, options));
  } else {
    if constexpr (HasDiagonalBlocksTangent<Law>::value) {
      if (options.psdMethod == PsdMethod::kDiagonalBlocks) {
        const Eigen::Vector3d sigma = clampedSingularValues(point, options);
        return Law::diagonalBlocksTangent(p, point.F, point.svd.U, point.svd.V, sigma);
      }
    }
    Matrix9d A = lawTangent<Law>(p, point.F);
    projectPsd(A);
    return A;
  }
}

}  // namespace tt
