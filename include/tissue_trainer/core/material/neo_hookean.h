#pragma once
// Compressible Neo-Hookean law (Bonet and Wood, "Nonlinear continuum mechanics for finite
// element analysis", Sec. 6.4.3):
//   psi = mu/2 (tr(F^T F) - 3) - mu ln J + lambda/2 (ln J)^2,   J = det F,
//   P = mu (F - F^-T) + lambda ln J F^-T,
//   dP = mu dF + (mu - lambda ln J) F^-T dF^T F^-T + lambda tr(F^-1 dF) F^-T.
// Defined for J > 0 only: an inverted element gives an infinite energy and a NaN stress, so
// scenes that may invert elements use it with inversion handling (law.h), which keeps J > 0.
#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <limits>

#include "tissue_trainer/core/model/material.h"

namespace tt {

struct NeoHookeanLaw {
  static constexpr const char* kName = "neo_hookean";
  static constexpr bool kIsotropic = true;

  struct Constants {
    double mu = 0.0, lambda = 0.0;
  };
  using Parameters = Constants;

  static Constants constants(const ElasticConstants& k) { return {k.mu, k.lambda}; }
  static Constants constants(const Material& m) { return constants(m.elasticConstants()); }
  static bool restStressFree(const Constants&) { return true; }
  static Parameters parameters(const Constants& k, const Eigen::Matrix3d&) { return k; }

  static double energy(const Parameters& p, const Eigen::Matrix3d& F) {
    const double J = F.determinant();
    if (!(J > 0.0)) return std::numeric_limits<double>::infinity();
    const double lnJ = std::log(J);
    return 0.5 * p.mu * (F.squaredNorm() - 3.0) - p.mu * lnJ + 0.5 * p.lambda * lnJ * lnJ;
  }
  static Eigen::Matrix3d stress(const Parameters& p, const Eigen::Matrix3d& F) {
    const double J = F.determinant();
    if (!(J > 0.0)) return Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
    const Eigen::Matrix3d FinvT = F.inverse().transpose();
    return p.mu * (F - FinvT) + (p.lambda * std::log(J)) * FinvT;
  }
  static Eigen::Matrix3d stressDifferential(const Parameters& p, const Eigen::Matrix3d& F,
                                            const Eigen::Matrix3d& dF) {
    const double J = F.determinant();
    if (!(J > 0.0)) return Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
    const Eigen::Matrix3d Finv = F.inverse();
    const Eigen::Matrix3d FinvT = Finv.transpose();
    const double lnJ = std::log(J);
    return p.mu * dF + (p.mu - p.lambda * lnJ) * (FinvT * dF.transpose() * FinvT) +
           (p.lambda * (Finv * dF).trace()) * FinvT;
  }
};

}  // namespace tt
