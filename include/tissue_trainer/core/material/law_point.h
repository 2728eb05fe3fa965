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

inline LawPoint lawPoint(const Eigen::Matrix3d& F, const LawOptions& options) {
  LawPoint point;
  if (options.inversionThreshold > 0.0) {
    point.svd = rotationSvd(F);
    point.hasSvd = true;
    point.F = clampedGradient(point.svd, options.inversionThreshold, point.clamped);
    if (!point.clamped) point.F = F;  // bitwise the same answers as without the option
  } else {
    point.F = F;
  }
  return point;
}

// The tangent used at the point: the law's, or its PSD projection.
template <class Law>
Matrix9d pointTangent(const typename Law::Parameters& p, LawPoint& point,
                      const LawOptions& options) {
  if (!options.psdProjection) return lawTangent<Law>(p, point.F);
  if constexpr (Law::kIsotropic) {
    if (!point.hasSvd) {
      point.svd = rotationSvd(point.F);
      point.hasSvd = true;
    }
    Eigen::Vector3d sigma = point.svd.sigma;
    if (options.inversionThreshold > 0.0) sigma = sigma.cwiseMax(options.inversionThreshold);
    return isotropicProjectedTangent<Law>(p, point.svd, sigma);
  } else {
    Matrix9d A = lawTangent<Law>(p, point.F);
    projectPsd(A);
    return A;
  }
}

}  // namespace tt
