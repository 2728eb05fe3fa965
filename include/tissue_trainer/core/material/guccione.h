#pragma once
// The transversely isotropic Guccione law of passive myocardium as the cardiac mechanics
// benchmark states it (Land et al., "Verification of cardiac mechanics software: benchmark
// problems and solutions for testing active and passive material behaviour", Proc. R. Soc. A
// 2015, Sec. 2b), with a volumetric penalty in place of exact incompressibility:
//   E = (F^T F - I)/2,   E_f = B^T E B   (B: fibre f, sheet s, sheet-normal n),
//   Q = b_f E_ff^2 + b_t (E_ss^2 + E_nn^2 + E_sn^2 + E_ns^2) + b_fs (E_fs^2 + E_sf^2 + E_fn^2
//       + E_nf^2) = sum_ij W_ij E_f,ij^2   (W: the symmetric weight matrix of b_f, b_t, b_fs),
//   psi = C/2 (e^Q - 1) + kappa/2 (J - 1)^2,   J = det F.
// Stress: S_f = d psi / dE_f = C e^Q (W o E_f) (o: entrywise product), S = B S_f B^T,
// P = F S + kappa (J - 1) cof F. Differential: dE_f = B^T sym(F^T dF) B,
// dS_f = C e^Q [W o dE_f + dQ (W o E_f)], dQ = 2 sum_ij W_ij E_f,ij dE_f,ij,
// dP = dF S + F B dS_f B^T + the volume term's (material/volume.h with p = kappa / 2, r = 1).
// The paper's law is incompressible (J = 1); the penalty's kappa (the small-strain bulk
// modulus) is a constant of the material, chosen as docs/materials.md explains. The energy
// is the paper's on every isochoric state. e^Q overflows to +inf past Q ~ 709 (a Green strain
// of several units): the stress is then not finite, and the stability guard rejects the step.
#include <Eigen/Core>
#include <cmath>

#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/volume.h"

namespace tt {

struct GuccioneConstants {
  double C = 0.0;            // Pa
  double bf = 0.0, bt = 0.0, bfs = 0.0;
  double bulkModulus = 0.0;  // kappa, Pa

  // Problem 1 of the benchmark (the beam): C = 2 kPa, b_f = 8, b_t = 2, b_fs = 4, here in Pa,
  // with the given bulk modulus.
  static GuccioneConstants landBeam(double bulkModulus) { return {2000.0, 8.0, 2.0, 4.0, bulkModulus}; }
};

struct GuccioneLaw {
  static constexpr const char* kName = "guccione";
  static constexpr bool kIsotropic = false;
  using Constants = GuccioneConstants;

  struct Parameters {
    double C = 0.0;
    Eigen::Matrix3d weights = Eigen::Matrix3d::Zero();  // W, in the fibre frame
    Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();  // B, orthonormal
    VolumeLaw::Parameters volume;
  };

  static bool restStressFree(const Constants&) { return true; }
  static Parameters parameters(const Constants& c, const Eigen::Matrix3d& frame) {
    Parameters p;
    p.C = c.C;
    p.weights << c.bf, c.bfs, c.bfs,  //
        c.bfs, c.bt, c.bt,            //
        c.bfs, c.bt, c.bt;
    p.frame = FibreTermLaw<PoleZeroTerm>::orthonormalFrame(frame);
    p.volume = {0.5 * c.bulkModulus, 1.0};
    return p;
  }

  static Eigen::Matrix3d frameStrain(const Parameters& p, const Eigen::Matrix3d& F) {
    return FibreTermLaw<PoleZeroTerm>::frameStrain(p.frame, F);
  }
  static double exponent(const Parameters& p, const Eigen::Matrix3d& Ef) {
    return (p.weights.array() * Ef.array().square()).sum();
  }

  static double energy(const Parameters& p, const Eigen::Matrix3d& F) {
    const double Q = exponent(p, frameStrain(p, F));
    return 0.5 * p.C * std::expm1(Q) + VolumeLaw::energy(p.volume, F);
  }

  static Eigen::Matrix3d stress(const Parameters& p, const Eigen::Matrix3d& F) {
    const Eigen::Matrix3d Ef = frameStrain(p, F);
    const Eigen::Matrix3d Sf = p.C * std::exp(exponent(p, Ef)) * p.weights.cwiseProduct(Ef);
    return F * (p.frame * Sf * p.frame.transpose()) + VolumeLaw::stress(p.volume, F);
  }

  static Eigen::Matrix3d stressDifferential(const Parameters& p, const Eigen::Matrix3d& F,
                                            const Eigen::Matrix3d& dF) {
    const Eigen::Matrix3d Ef = frameStrain(p, F);
    const Eigen::Matrix3d WEf = p.weights.cwiseProduct(Ef);
    const double scale = p.C * std::exp(exponent(p, Ef));
    const Eigen::Matrix3d G = F.transpose() * dF;
    const Eigen::Matrix3d dEf = p.frame.transpose() * (0.5 * (G + G.transpose())) * p.frame;
    const double dQ = 2.0 * (WEf.array() * dEf.array()).sum();
    const Eigen::Matrix3d dSf = scale * (p.weights.cwiseProduct(dEf) + dQ * WEf);
    return dF * (p.frame * (scale * WEf) * p.frame.transpose()) +
           F * (p.frame * dSf * p.frame.transpose()) +
           VolumeLaw::stressDifferential(p.volume, F, dF);
  }
};

}  // namespace tt
