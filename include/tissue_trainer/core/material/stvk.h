#pragma once
// Transversely isotropic St Venant-Kirchhoff law, the energy of the tet models of Jeffrey, "A
// non-linear anisotropic finite element method for surgical simulation" (edge_length,
// stvk_displacement; their fast kernels keep their own copy in model/stvk_kernel.h):
//   psi = lambda/2 tr(E)^2 + mu tr(E^2) + c (a0 . E a0)^2,   E = (F^T F - I)/2,
//   S = lambda tr(E) I + 2 mu E + 2 c (a0 . E a0) a0 a0^T,    P = F S,
// with a0 the element's fibre axis and c = (lambda_L - lambda)/2 + (mu_L - mu) from the
// longitudinal Lame constants (Material::fibreCoefficient).
#include <Eigen/Core>

#include "tissue_trainer/core/model/material.h"

namespace tt {

struct StvkLaw {
  static constexpr const char* kName = "stvk";
  static constexpr bool kIsotropic = false;

  struct Constants {
    double lambda = 0.0, mu = 0.0, c = 0.0;
  };
  struct Parameters {
    double lambda = 0.0, mu = 0.0, c = 0.0;
    Eigen::Vector3d fibre = Eigen::Vector3d::UnitX();  // unit a0
  };

  static Constants constants(const ElasticConstants& k) {
    return {k.lambda, k.mu, k.fibreCoefficient()};
  }
  static Constants constants(const Material& m) { return constants(m.elasticConstants()); }
  static bool restStressFree(const Constants&) { return true; }
  static Parameters parameters(const Constants& k, const Eigen::Matrix3d& frame) {
    return {k.lambda, k.mu, k.c, frame.col(0).normalized()};
  }

  static Eigen::Matrix3d secondPiola(const Parameters& p, const Eigen::Matrix3d& E) {
    Eigen::Matrix3d S = 2.0 * p.mu * E;
    S.diagonal().array() += p.lambda * E.trace();
    S.noalias() += (2.0 * p.c * p.fibre.dot(E * p.fibre)) * p.fibre * p.fibre.transpose();
    return S;
  }
  static Eigen::Matrix3d strain(const Eigen::Matrix3d& F) {
    return 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
  }

  static double energy(const Parameters& p, const Eigen::Matrix3d& F) {
    const Eigen::Matrix3d E = strain(F);
    const double tr = E.trace(), fibreStrain = p.fibre.dot(E * p.fibre);
    return 0.5 * p.lambda * tr * tr + p.mu * E.squaredNorm() + p.c * fibreStrain * fibreStrain;
  }
  static Eigen::Matrix3d stress(const Parameters& p, const Eigen::Matrix3d& F) {
    return F * secondPiola(p, strain(F));
  }
  // dP = dF S + F dS with dE = sym(F^T dF); dS is S's linear formula at dE.
  static Eigen::Matrix3d stressDifferential(const Parameters& p, const Eigen::Matrix3d& F,
                                            const Eigen::Matrix3d& dF) {
    const Eigen::Matrix3d FtdF = F.transpose() * dF;
    const Eigen::Matrix3d dE = 0.5 * (FtdF + FtdF.transpose());
    return dF * secondPiola(p, strain(F)) + F * secondPiola(p, dE);
  }
};

}  // namespace tt
