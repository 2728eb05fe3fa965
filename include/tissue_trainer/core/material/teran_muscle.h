#pragma once
// The active muscle law of M. Bao, "Derivation of Quasistatics and Landmark Optimization for
// Muscles" (Sec. 4.3, Eq. 10), after Teran, Sifakis, Irving and Fedkiw, "Robust quasistatic
// finite elements and flesh simulation" (2005):
//   psi = A I1~ + B I2~ + K/2 (ln J)^2 + sigma_max (alpha Phi_a(lam) + Phi_p(lam)),
//   I1~ = J^(-2/3) tr C,  I2~ = J^(-4/3) (tr(C)^2 - tr(C^2))/2,  C = F^T F,
// with the fibre stretch lam = J^(-1/3) |F a0| (deviatoric, as Eq. 10 is written) or
// lam = |F a0| (non-deviatoric, the model the paper's Eq. 45 differentiates). psi(I) = 3 (A + B):
// the constant is kept, as Eq. 10 is written.
//
// Fibre curves (the paper leaves them open): with e = lam - 1 and tau = d psi_f / d lam =
// sigma_max (alpha t_a + t_p), the C1 curves of PhysBAM's FACE_3D (so psi is C2):
//   t_p = 0 (lam <= 1);  p1 (exp(p2 e) - p2 e - 1) (lam <= 1.4);  p3 lam + p4 (beyond),
//   t_a = 1 - 25/6 e^2 (|e| < 0.4);  25/3 (|e| - 0.6)^2 (|e| < 0.6);  0 (beyond),
// and Phi_a, Phi_p their integrals from lam = 1.
//
// P and dP are the closed-form derivatives of psi at F (valid for a general F, no SVD). The
// paper's route through the singular-value frame (Eq. 15, the alpha/beta/eta blocks of
// Sec. 4.5.1.4, Eq. 45) is teran_muscle_svd_frame.h; the tests TeranMuscleSvdFrame.* hold the
// two equal to round-off (docs/muscles.md, "The singular-value frame"). Defined for J > 0 only:
// an inverted element gives an infinite energy and a NaN stress, so inverting scenes use
// inversion handling (law.h).
#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "tissue_trainer/core/material/psd_projection.h"

namespace tt {

// The fibre curves, dimensionless (times sigma_max in the law).
struct MuscleFibreCurves {
  static constexpr double p1 = 0.05, p2 = 6.6;
  static double p3() { return p1 * p2 * (std::exp(0.4 * p2) - 1.0); }
  static double p4() { return p1 * (std::exp(0.4 * p2) * (1.0 - 1.4 * p2) + p2 - 1.0); }

  // Passive tension t_p(lam), its derivative and its integral Phi_p from 1.
  static void passive(double lam, double& phi, double& t, double& dt) {
    const double e = lam - 1.0;
    if (lam <= 1.0) {
      phi = t = dt = 0.0;
    } else if (lam <= 1.4) {
      const double x = std::exp(p2 * e);
      phi = p1 * ((x - 1.0) / p2 - 0.5 * p2 * e * e - e);
      t = p1 * (x - p2 * e - 1.0);
      dt = p1 * p2 * (x - 1.0);
    } else {
      double phi14, t14, dt14;
      passive(1.4, phi14, t14, dt14);
      phi = phi14 + 0.5 * p3() * (lam * lam - 1.96) + p4() * (lam - 1.4);
      t = p3() * lam + p4();
      dt = p3();
    }
  }
  // Active tension t_a(lam), its derivative and its integral Phi_a from 1.
  static void active(double lam, double& phi, double& t, double& dt) {
    const double e = lam - 1.0, a = std::abs(e), s = e < 0.0 ? -1.0 : 1.0;
    if (a < 0.4) {
      phi = s * (a - 25.0 / 18.0 * a * a * a);
      t = 1.0 - 25.0 / 6.0 * e * e;
      dt = -25.0 / 3.0 * e;
    } else if (a < 0.6) {
      const double g04 = 0.4 - 25.0 / 18.0 * 0.064, d = a - 0.6;
      phi = s * (g04 + 50.0 / 18.0 * (d * d * d + 0.008));
      t = 25.0 / 3.0 * d * d;
      dt = s * 50.0 / 3.0 * d;
    } else {
      phi = s / 3.0;
      t = dt = 0.0;
    }
  }
};

struct TeranMuscleLaw {
  static constexpr const char* kName = "teran_muscle";
  static constexpr bool kIsotropic = false;

  struct Constants {
    double A = 6e4, B = 2e4, K = 6e4;  // Pa: Mooney-Rivlin pair and bulk modulus
    double sigmaMax = 3e5;              // Pa: peak isometric stress
    double activation = 0.0;            // alpha in [0, 1]
    bool deviatoricStretch = true;      // lam = J^(-1/3) |F a0| (else |F a0|)
    bool passiveFibre = true;           // false: no t_p (with A = B = K = 0 and alpha = 1,
                                        // the law is d psi / d alpha, the fitting's term)
  };
  struct Parameters {
    Constants k;
    Eigen::Vector3d a0 = Eigen::Vector3d::UnitX();  // unit fibre direction at rest
  };

  static bool restStressFree(const Constants& k) { return k.activation == 0.0; }
  static double restEnergy(const Constants& k) { return 3.0 * (k.A + k.B); }
  // The law of d psi / d alpha = sigma_max Phi_a(lam): psi is linear in alpha.
  static Constants activationTerm(Constants k) {
    k.A = k.B = k.K = 0.0;
    k.activation = 1.0;
    k.passiveFibre = false;
    return k;
  }
  static Parameters parameters(const Constants& k, const Eigen::Matrix3d& frame) {
    return {k, frame.col(0).normalized()};
  }

  // psi_f, tau = d psi_f / d lam and d tau / d lam.
  static void fibre(const Constants& k, double lam, double& psi, double& tau, double& dtau) {
    double pa, ta, da, pp, tp, dp;
    MuscleFibreCurves::active(lam, pa, ta, da);
    pp = tp = dp = 0.0;
    if (k.passiveFibre) MuscleFibreCurves::passive(lam, pp, tp, dp);
    psi = k.sigmaMax * (k.activation * pa + pp);
    tau = k.sigmaMax * (k.activation * ta + tp);
    dtau = k.sigmaMax * (k.activation * da + dp);
  }

  static double energy(const Parameters& p, const Eigen::Matrix3d& F) {
    const double J = F.determinant();
    if (!(J > 0.0)) return std::numeric_limits<double>::infinity();
    const Eigen::Matrix3d C = F.transpose() * F;
    const double trC = C.trace(), I2 = 0.5 * (trC * trC - C.squaredNorm()), lnJ = std::log(J);
    double psi, tau, dtau;
    fibre(p.k, stretch(p, F, J), psi, tau, dtau);
    return p.k.A * std::pow(J, -2.0 / 3.0) * trC + p.k.B * std::pow(J, -4.0 / 3.0) * I2 +
           0.5 * p.k.K * lnJ * lnJ + psi;
  }

  static Eigen::Matrix3d stress(const Parameters& p, const Eigen::Matrix3d& F) {
    const double J = F.determinant();
    if (!(J > 0.0)) return Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
    const State s(p, F, J);
    return 2.0 * p.k.A * s.j2 * (F - s.trC / 3.0 * s.FinvT) +
           p.k.B * s.j4 * (s.G - 4.0 / 3.0 * s.I2 * s.FinvT) + p.k.K * s.lnJ * s.FinvT +
           s.tau * s.D;
  }

  static Eigen::Matrix3d stressDifferential(const Parameters& p, const Eigen::Matrix3d& F,
                                            const Eigen::Matrix3d& dF) {
    const double J = F.determinant();
    if (!(J > 0.0)) return Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
    return differential(p, State(p, F, J), F, dF);
  }

  // The 9 x 9 tangent (column c: the differential for the unit dF(c % 3, c / 3)) with the nine
  // differentials sharing one State: bitwise the columns of stressDifferential.
  static Eigen::Matrix<double, 9, 9> tangent(const Parameters& p, const Eigen::Matrix3d& F) {
    const double J = F.determinant();
    if (!(J > 0.0))
      return Eigen::Matrix<double, 9, 9>::Constant(std::numeric_limits<double>::quiet_NaN());
    const State s(p, F, J);
    Eigen::Matrix<double, 9, 9> A;
    for (int c = 0; c < 9; ++c) {
      Eigen::Matrix3d dF = Eigen::Matrix3d::Zero();
      dF(c % 3, c / 3) = 1.0;
      const Eigen::Matrix3d dP = differential(p, s, F, dF);
      A.col(c) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dP.data());
    }
    return A;
  }

  // The paper's PSD projection (Sec. 5.6, after Teran, Sifakis, Irving and Fedkiw 2005,
  // Sec. 5) of the tangent at F = U diag(sigma) V^T (U, V rotations): the isotropic part's
  // tangent in the singular-value frame is block-diagonal (the 3 x 3 block of the diagonal
  // entries and the 2 x 2 blocks of the pairs (F_ij, F_ji), Sec. 4.5.1); each block's negative
  // eigenvalues are set to zero and the result turned back with U and V. The fibre term is
  // added on its own, made PSD:
  //  - lam = |F a0| (the model of Eq. 45): dP_f = (c1 u + c2 (b.u) b) a0^T with u = dF a0,
  //    b = F a0, c1 = tau / lam, c2 = (tau' - c1) / lam^2, where dF : dP_f =
  //    |u|^2 (c1 sin^2 + tau' cos^2) of the angle between u and b; tau >= 0 for these curves,
  //    so clamping tau' at zero (PhysBAM's max(0, Tension_Derivative)) makes it PSD;
  //  - lam = J^(-1/3) |F a0| (Eq. 10 as written): the paper gives no differential of this
  //    term, and it is not of that form; its exact 9 x 9 tangent has its negative
  //    eigenvalues set to zero.
  // A sum of PSD matrices, so PSD; where the unprojected tangent's parts are already PSD
  // (small stretches, fibre at rest) it is the tangent itself.
  static Eigen::Matrix<double, 9, 9> diagonalBlocksTangent(const Parameters& p,
                                                           const Eigen::Matrix3d& F,
                                                           const Eigen::Matrix3d& U,
                                                           const Eigen::Matrix3d& V,
                                                           const Eigen::Vector3d& sigma) {
    Parameters isotropic = p;
    isotropic.k.sigmaMax = 0.0;  // tau = tau' = 0: the fibre term drops out
    Eigen::Matrix<double, 9, 9> Ahat = tangent(isotropic, Eigen::Matrix3d(sigma.asDiagonal()));
    projectDiagonalFrameBlocks(Ahat);
    const Eigen::Matrix<double, 9, 9> R = frameRotation(U, V);
    Eigen::Matrix<double, 9, 9> A = R * Ahat * R.transpose();
    addProjectedFibreTangent(p, F, A);
    return A;
  }

 private:
  static void addProjectedFibreTangent(const Parameters& p, const Eigen::Matrix3d& F,
                                       Eigen::Matrix<double, 9, 9>& A) {
    if (p.k.deviatoricStretch) {
      Parameters fibre = p;
      fibre.k.A = fibre.k.B = fibre.k.K = 0.0;
      Eigen::Matrix<double, 9, 9> Af = tangent(fibre, F);
      projectPsd(Af);
      A += Af;
      return;
    }
    const Eigen::Vector3d b = F * p.a0;
    const double lam = b.norm();
    if (!(lam > 0.0)) return;  // |F a0| = 0 needs lam < 0.4, where both curves are zero
    double psi, tau, dtau;
    fibre(p.k, lam, psi, tau, dtau);
    const double c1 = tau / lam, c2 = (std::max(dtau, 0.0) - c1) / (lam * lam);
    // entry (i + 3 j, k + 3 l) = a0_j a0_l (c1 delta_ik + c2 b_i b_k)
    Eigen::Matrix3d S = c2 * b * b.transpose();
    S.diagonal().array() += c1;
    for (int l = 0; l < 3; ++l)
      for (int j = 0; j < 3; ++j)
        A.block<3, 3>(3 * j, 3 * l) += (p.a0(j) * p.a0(l)) * S;
  }

  static double stretch(const Parameters& p, const Eigen::Matrix3d& F, double J) {
    const double n = (F * p.a0).norm();
    return p.k.deviatoricStretch ? std::cbrt(1.0 / J) * n : n;
  }

  // What P and dP share at one F; D = d lam / dF.
  struct State {
    Eigen::Matrix3d C, Finv, FinvT, G, D;
    Eigen::Vector3d b;  // F a0
    double trC, I2, lnJ, j2, j4, j1, n, lam, tau, dtau;

    State(const Parameters& p, const Eigen::Matrix3d& F, double J)
        : C(F.transpose() * F), Finv(F.inverse()), FinvT(Finv.transpose()), b(F * p.a0) {
      trC = C.trace();
      I2 = 0.5 * (trC * trC - C.squaredNorm());
      G = 2.0 * (trC * F - F * C);  // d I2 / dF
      lnJ = std::log(J);
      j1 = p.k.deviatoricStretch ? std::cbrt(1.0 / J) : 1.0;
      j2 = std::pow(J, -2.0 / 3.0);
      j4 = j2 * j2;
      n = b.norm();
      lam = j1 * n;
      double psi;
      fibre(p.k, lam, psi, tau, dtau);
      // |F a0| = 0 needs lam < 0.4, where both curves are zero.
      D = n > 0.0 ? Eigen::Matrix3d(j1 / n * b * p.a0.transpose()) : Eigen::Matrix3d::Zero();
      if (p.k.deviatoricStretch) D -= lam / 3.0 * FinvT;
    }
  };

  // dP for dF at F, with the State of F.
  static Eigen::Matrix3d differential(const Parameters& p, const State& s,
                                      const Eigen::Matrix3d& F, const Eigen::Matrix3d& dF) {
    const double t = (s.Finv * dF).trace();  // dJ / J
    const Eigen::Matrix3d dFinvT = -s.FinvT * dF.transpose() * s.FinvT;
    const double dtrC = 2.0 * (F.array() * dF.array()).sum();
    const Eigen::Matrix3d dC = dF.transpose() * F + F.transpose() * dF;
    const Eigen::Matrix3d dG = 2.0 * (dtrC * F + s.trC * dF - dF * s.C - F * dC);
    const double dI2 = (s.G.array() * dF.array()).sum();
    const Eigen::Matrix3d PA = F - s.trC / 3.0 * s.FinvT;
    const Eigen::Matrix3d PB = s.G - 4.0 / 3.0 * s.I2 * s.FinvT;
    Eigen::Matrix3d dP =
        2.0 * p.k.A * s.j2 * (-2.0 / 3.0 * t * PA + dF - dtrC / 3.0 * s.FinvT - s.trC / 3.0 * dFinvT);
    dP += p.k.B * s.j4 *
          (-4.0 / 3.0 * t * PB + dG - 4.0 / 3.0 * (dI2 * s.FinvT + s.I2 * dFinvT));
    dP += p.k.K * (t * s.FinvT + s.lnJ * dFinvT);
    return dP + fibreDifferential(p, s, dF, t, dFinvT);
  }

  // d(tau D) = dtau dlam D + tau dD.
  static Eigen::Matrix3d fibreDifferential(const Parameters& p, const State& s,
                                           const Eigen::Matrix3d& dF, double t,
                                           const Eigen::Matrix3d& dFinvT) {
    if (!(s.n > 0.0) || (s.tau == 0.0 && s.dtau == 0.0)) return Eigen::Matrix3d::Zero();
    const Eigen::Vector3d u = dF * p.a0;
    const double dlam = (s.D.array() * dF.array()).sum();
    const double bu = s.b.dot(u);
    // d(b a0^T / n) = (u - (b.u / n^2) b) a0^T / n
    Eigen::Matrix3d dD = s.j1 / s.n * (u - bu / (s.n * s.n) * s.b) * p.a0.transpose();
    if (p.k.deviatoricStretch) {
      dD -= t / 3.0 * (s.j1 / s.n) * s.b * p.a0.transpose();  // d J^(-1/3) = -t/3 J^(-1/3)
      dD -= dlam / 3.0 * s.FinvT + s.lam / 3.0 * dFinvT;
    }
    return s.dtau * dlam * s.D + s.tau * dD;
  }
};

}  // namespace tt
