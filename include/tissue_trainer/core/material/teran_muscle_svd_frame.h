#pragma once
// The muscle law's stress and stiffness computed through the singular-value frame, as M. Bao,
// "Derivation of Quasistatics and Landmark Optimization for Muscles" derives them, beside the
// law's direct derivatives (teran_muscle.h), which the tests hold them equal to. With
// F = U diag(sigma) V^T (det U det V = +1) and the fibre direction in the frame f = V^T a0:
//   P(F) = U P^(sigma; f) V^T,   dP = U [dP^ : (U^T dF V)] V^T,
// because the law is frame indifferent, P(Q F R) = Q P(F; R a0) R for rotations Q, R.
//
// P^ is Eq. 15 (Sec. 4.3.4), read as its derivation needs: C = F^^2 is non-deviatoric, so
// w12 = 2 A Jcc + 2 B Jcc^2 tr C and p_f = (w12 tr C - w2 tr C^2 + T lam^2) / 3, with T = tau / lam
// (the T of Sec. 4.3.3) and the deviatoric lam = J^(-1/3) |F^ f| of Eq. 10. For lam = |F^ f| (the
// stretch Eq. 45 differentiates) the fibre term is (tau / lam) F^ f f^T and p_f loses T lam^2.
//
// dP^ of the isotropic part: the alpha/beta/eta blocks of the summary of Sec. 4.5.1.4 with two
// corrections (alpha_ij has tr C - sigma_i^2 - sigma_j^2; eta13 has -(8B/3) Jcc^2 tr C): a 3 x 3
// block A = diag(alpha_ii + beta_ii) + F_base eta F_base^T on (F^_11, F^_22, F^_33) and a 2 x 2
// block [[alpha_ij, beta_ij], [beta_ij, alpha_ij]] on each pair (F^_ij, F^_ji). For this energy
// the blocks divide only by sigma_i sigma_j, never by sigma_i - sigma_j (the general isotropic
// form of Teran et al. 2005 does), so repeated singular values need no limit form. The fibre
// term: Eq. 45 for lam = |F^ f| (there T = tau, so c1 = tau / lam, c2 = (tau' - c1) / lam^2);
// the paper gives none for the deviatoric lam, whose exact differential in the frame is
// d(tau D) = tau' (D : dF^) D + tau dD with D = d lam / dF^ = J^(-1/3) b f^T / |b| - lam/3 F^^-1,
// b = F^ f.
//
// Defined for sigma with a positive product, as the law: otherwise NaN. Inversion handling
// passes the clamped singular values of rotationSvd (max(sigma_i, threshold)), which gives the
// law's answers at F_c = U diag(max(sigma, threshold)) V^T (law_point.h).
#include <Eigen/Core>
#include <cmath>
#include <limits>

#include "tissue_trainer/core/material/law.h"
#include "tissue_trainer/core/material/teran_muscle.h"

namespace tt {

struct TeranMuscleSvdFrame {
  using Law = TeranMuscleLaw;

  // The isotropic part's tangent at diag(sigma) as its blocks (Sec. 4.5.1.4).
  struct IsotropicBlocks {
    Eigen::Matrix3d diagonal;  // on (F_11, F_22, F_33)
    double alpha[3][3], beta[3][3];
  };

  static IsotropicBlocks isotropicBlocks(const Law::Constants& k, const Eigen::Vector3d& s) {
    const double J = s.prod(), Jcc = std::pow(J, -2.0 / 3.0), lnJ = std::log(J);
    const Eigen::Vector3d s2 = s.cwiseProduct(s);
    const double trC = s2.sum(), trC2 = s2.squaredNorm();
    const double betaNumerator =
        2.0 / 3.0 * Jcc * (k.A * trC + k.B * Jcc * (trC * trC - trC2)) - k.K * lnJ;
    IsotropicBlocks m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        m.alpha[i][j] = 2.0 * Jcc * (k.A + k.B * Jcc * (trC - s2(i) - s2(j)));
        m.beta[i][j] = betaNumerator / (s(i) * s(j)) - 2.0 * k.B * Jcc * Jcc * s(i) * s(j);
      }
    Eigen::Matrix3d eta;
    eta(0, 0) = 4.0 * k.B * Jcc * Jcc;
    eta(0, 1) = eta(1, 0) = eta(1, 1) = 0.0;
    eta(0, 2) = eta(2, 0) = -Jcc / 3.0 * (4.0 * k.A + 8.0 * k.B * Jcc * trC);
    eta(1, 2) = eta(2, 1) = 8.0 * k.B / 3.0 * Jcc * Jcc;
    eta(2, 2) = Jcc / 9.0 * (4.0 * k.A * trC + 8.0 * k.B * Jcc * (trC * trC - trC2)) + k.K;
    Eigen::Matrix3d base;  // F_base: rows (sigma_i, sigma_i^3, 1 / sigma_i)
    for (int i = 0; i < 3; ++i) base.row(i) << s(i), s2(i) * s(i), 1.0 / s(i);
    m.diagonal = base * eta * base.transpose();
    for (int i = 0; i < 3; ++i) m.diagonal(i, i) += m.alpha[i][i] + m.beta[i][i];
    return m;
  }

  // P^ = P(diag(s)) for the fibre direction f (Eq. 15).
  static Eigen::Matrix3d diagonalStress(const Law::Constants& k, const Eigen::Vector3d& s,
                                        const Eigen::Vector3d& f) {
    const double J = s.prod();
    if (!(J > 0.0)) return Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
    const double Jcc = std::pow(J, -2.0 / 3.0);
    const Eigen::Vector3d s2 = s.cwiseProduct(s);
    const double trC = s2.sum(), trC2 = s2.squaredNorm();
    const double w2 = 2.0 * Jcc * Jcc * k.B, w12 = 2.0 * Jcc * k.A + trC * w2;
    const Fibre fib(k, s, f, J);
    double pf = (w12 * trC - w2 * trC2) / 3.0;
    Eigen::Matrix3d P;
    if (k.deviatoricStretch) {
      const double T = fib.lam > 0.0 ? fib.tau / fib.lam : 0.0;  // Sec. 4.3.3's T
      pf += T * fib.lam * fib.lam / 3.0;
      P = (Jcc * T) * fib.b * f.transpose();
    } else {
      P = (fib.lam > 0.0 ? fib.tau / fib.lam : 0.0) * fib.b * f.transpose();
    }
    const double p = k.K * std::log(J);
    P.diagonal() += w12 * s - w2 * s2.cwiseProduct(s) + (p - pf) * s.cwiseInverse();
    return P;
  }

  // P at F = U diag(sigma) V^T.
  static Eigen::Matrix3d stress(const Law::Parameters& p, const Eigen::Matrix3d& U,
                                const Eigen::Vector3d& sigma, const Eigen::Matrix3d& V) {
    return U * diagonalStress(p.k, sigma, V.transpose() * p.a0) * V.transpose();
  }

  // dP^ at diag(s) for dF^ (in the frame).
  static Eigen::Matrix3d diagonalStressDifferential(const Law::Constants& k,
                                                    const Eigen::Vector3d& s,
                                                    const Eigen::Vector3d& f,
                                                    const Eigen::Matrix3d& dFhat) {
    const double J = s.prod();
    if (!(J > 0.0)) return Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
    return isotropicDifferential(isotropicBlocks(k, s), dFhat) +
           fibreDifferential(k, Fibre(k, s, f, J), s, f, dFhat);
  }

  // dP at F = U diag(sigma) V^T for dF.
  static Eigen::Matrix3d stressDifferential(const Law::Parameters& p, const Eigen::Matrix3d& U,
                                            const Eigen::Vector3d& sigma,
                                            const Eigen::Matrix3d& V, const Eigen::Matrix3d& dF) {
    return U *
           diagonalStressDifferential(p.k, sigma, V.transpose() * p.a0, U.transpose() * dF * V) *
           V.transpose();
  }

  // The 9 x 9 tangent on vec(F) (column c: dP for the unit dF(c % 3, c / 3)), as the law's.
  static Matrix9d tangent(const Law::Parameters& p, const Eigen::Matrix3d& U,
                          const Eigen::Vector3d& sigma, const Eigen::Matrix3d& V) {
    const double J = sigma.prod();
    if (!(J > 0.0)) return Matrix9d::Constant(std::numeric_limits<double>::quiet_NaN());
    const Eigen::Vector3d f = V.transpose() * p.a0;
    const IsotropicBlocks blocks = isotropicBlocks(p.k, sigma);
    const Fibre fib(p.k, sigma, f, J);
    Matrix9d A;
    for (int c = 0; c < 9; ++c) {
      // U^T e_k e_l^T V for the unit dF(k, l)
      const Eigen::Matrix3d dFhat = U.row(c % 3).transpose() * V.row(c / 3);
      const Eigen::Matrix3d dP =
          U *
          (isotropicDifferential(blocks, dFhat) + fibreDifferential(p.k, fib, sigma, f, dFhat)) *
          V.transpose();
      A.col(c) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dP.data());
    }
    return A;
  }

 private:
  // The fibre's stretch and tension at diag(s).
  struct Fibre {
    Eigen::Vector3d b;  // F^ f
    double n, jc, lam, tau, dtau;
    Fibre(const Law::Constants& k, const Eigen::Vector3d& s, const Eigen::Vector3d& f, double J)
        : b(s.cwiseProduct(f)), n(b.norm()) {
      jc = k.deviatoricStretch ? std::cbrt(1.0 / J) : 1.0;
      lam = jc * n;
      double psi;
      Law::fibre(k, lam, psi, tau, dtau);
    }
  };

  static Eigen::Matrix3d isotropicDifferential(const IsotropicBlocks& m,
                                               const Eigen::Matrix3d& dFhat) {
    Eigen::Matrix3d dP;
    dP.diagonal() = m.diagonal * dFhat.diagonal();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (i != j) dP(i, j) = m.alpha[i][j] * dFhat(i, j) + m.beta[i][j] * dFhat(j, i);
    return dP;
  }

  static Eigen::Matrix3d fibreDifferential(const Law::Constants& k, const Fibre& fib,
                                           const Eigen::Vector3d& s, const Eigen::Vector3d& f,
                                           const Eigen::Matrix3d& dFhat) {
    // |F^ f| = 0 needs lam < 0.4, where both tension curves are zero.
    if (!(fib.n > 0.0) || (fib.tau == 0.0 && fib.dtau == 0.0)) return Eigen::Matrix3d::Zero();
    const Eigen::Vector3d u = dFhat * f;
    const double bu = fib.b.dot(u);
    if (!k.deviatoricStretch) {  // Eq. 45
      const double c1 = fib.tau / fib.lam, c2 = (fib.dtau - c1) / (fib.lam * fib.lam);
      return (c1 * u + c2 * bu * fib.b) * f.transpose();
    }
    const Eigen::Vector3d sInv = s.cwiseInverse();
    const double t = dFhat.diagonal().dot(sInv);  // dJ / J
    Eigen::Matrix3d D = (fib.jc / fib.n) * fib.b * f.transpose();
    D.diagonal() -= fib.lam / 3.0 * sInv;
    const double dlam = (D.array() * dFhat.array()).sum();
    // d(J^(-1/3) b f^T / n) with dJ^(-1/3) = -t/3 J^(-1/3); d(F^^-T) = -F^^-1 dF^^T F^^-1
    Eigen::Matrix3d dD =
        (fib.jc / fib.n) * (u - (bu / (fib.n * fib.n) + t / 3.0) * fib.b) * f.transpose();
    dD += fib.lam / 3.0 * sInv.asDiagonal() * dFhat.transpose() * sInv.asDiagonal();
    dD.diagonal() -= dlam / 3.0 * sInv;
    return fib.dtau * dlam * D + fib.tau * dD;
  }
};

}  // namespace tt
