#pragma once
// The Hunter pole-zero law of myocardium as "Adamss: Advanced Anisotropic Mass-Spring System"
// states it (Sec. 2.8.1, Eq. 2.153, parameters in Table 2.1), written in the element's fibre
// frame B (columns: fibre 1, sheet 2, sheet-normal 3):
//   E = (F^T F - I)/2,   E_f = B^T E B,
//   psi = sum over ij in (11, 22, 33, 12, 13, 23) of w_ij(E_f,ij),
//   w(e) = k e^2 / (a - e)^b              (e < a; a is the term's pole),
//   w'(e) = k e (a - e)^(-b-1) [2 (a - e) + b e],
//   w''(e) = k (a - e)^(-b-2) [2 (a - e)^2 + 4 b e (a - e) + b (b + 1) e^2].
// Stress convention: each shear pair appears once in psi, so with a symmetric E the second
// Piola-Kirchhoff stress 2 d psi / dC has S_f,ii = w_ii'(E_f,ii) and
// S_f,ij = S_f,ji = w_ij'(E_f,ij) / 2 (i != j); S = B S_f B^T and P = F S = d psi / dF. The
// Table 2.1 row labelled beta holds the exponents b.
//
// The chapter prints |a - E|^b. Beyond a pole (E_f,ij >= a_ij) that expression falls again
// from infinity, a stress with no physical meaning (Sec. 2.9.2); this law gives an infinite
// energy and a NaN stress there instead (as neo_hookean does for J <= 0), so a step that
// crosses a pole is a non-finite state the stability guard rejects. The pole-free substitute
// of Sec. 2.9.2 is the law hunter_polynomial (material/hunter_polynomial.h).
//
// Both laws share FibreTermLaw below: an energy that is a sum of one function per fibre-frame
// Green strain component, the function given by a small Term type.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>

namespace tt {

// The six strain components of the pole-zero law, in the order of Eq. 2.153 and Table 2.1.
inline constexpr int kFibreTermRow[6] = {0, 1, 2, 0, 0, 1};
inline constexpr int kFibreTermCol[6] = {0, 1, 2, 1, 2, 2};
inline constexpr const char* kFibreTermLabel[6] = {"11", "22", "33", "12", "13", "23"};

// The parameters of the pole-zero law, one per term in the order above; k in Pa.
struct HunterConstants {
  std::array<double, 6> k{}, a{}, b{};

  // Table 2.1 ("Parameters for the energy density function proposed by Hunter et al.
  // adapted to canine myocardium"): k in kPa there, here in Pa.
  static HunterConstants table21() {
    HunterConstants c;
    c.k = {2842.0, 63.0, 310.0, 1000.0, 1000.0, 1000.0};
    c.a = {0.318, 0.429, 1.037, 0.731, 0.731, 0.886};
    c.b = {0.624, 2.48, 0.398, 2.0, 2.0, 2.0};
    return c;
  }
};

// One term w(e) = k e^2 / (a - e)^b of Eq. 2.153, defined for e < a.
struct PoleZeroTerm {
  double k = 0.0, a = 1.0, b = 0.0;

  bool admissible(double e) const { return e < a; }
  double value(double e) const { return k * e * e * std::pow(a - e, -b); }
  // w' and w'' with one pow.
  void derivatives(double e, double& first, double& second) const {
    const double d = a - e;
    const double g = std::pow(d, -b - 2.0);  // (a - e)^(-b-2)
    first = k * e * g * d * (2.0 * d + b * e);
    second = k * g * (2.0 * d * d + 4.0 * b * e * d + b * (b + 1.0) * e * e);
  }
  double first(double e) const {
    double w1, w2;
    derivatives(e, w1, w2);
    return w1;
  }
};

// A law psi = sum_t w_t(E_f,t) over the six fibre-frame Green strain components t, with the
// functions w_t given by Term (admissible(e), value(e), derivatives(e, w', w'')). Outside
// every term's admissible range the energy is +inf and the stress NaN. The frame is made
// orthonormal (Gram-Schmidt from its fibre column), as the strain components need.
template <class Term>
struct FibreTermLaw {
  static constexpr bool kIsotropic = false;

  struct Parameters {
    std::array<Term, 6> terms;
    Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();  // B: fibre, sheet, sheet-normal
  };

  static Eigen::Matrix3d orthonormalFrame(const Eigen::Matrix3d& frame) {
    Eigen::Matrix3d B;
    B.col(0) = frame.col(0).normalized();
    Eigen::Vector3d sheet = frame.col(1) - B.col(0).dot(frame.col(1)) * B.col(0);
    if (!(sheet.norm() > 1e-12 * frame.col(1).norm())) sheet = B.col(0).unitOrthogonal();
    B.col(1) = sheet.normalized();
    B.col(2) = B.col(0).cross(B.col(1));
    return B;
  }

  // E_f = B^T E B, E = (F^T F - I)/2 (E first: exactly zero at F = I whatever B's rounding).
  static Eigen::Matrix3d frameStrain(const Eigen::Matrix3d& B, const Eigen::Matrix3d& F) {
    const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
    return B.transpose() * E * B;
  }

  static bool admissible(const Parameters& p, const Eigen::Matrix3d& Ef) {
    for (int t = 0; t < 6; ++t)
      if (!p.terms[t].admissible(Ef(kFibreTermRow[t], kFibreTermCol[t]))) return false;
    return true;
  }

  static double energy(const Parameters& p, const Eigen::Matrix3d& F) {
    const Eigen::Matrix3d Ef = frameStrain(p.frame, F);
    if (!admissible(p, Ef)) return std::numeric_limits<double>::infinity();
    double psi = 0.0;
    for (int t = 0; t < 6; ++t) psi += p.terms[t].value(Ef(kFibreTermRow[t], kFibreTermCol[t]));
    return psi;
  }

  // S_f (fibre frame) and, when wanted, the six w'' for the differential. False beyond a pole.
  static bool frameStress(const Parameters& p, const Eigen::Matrix3d& Ef, Eigen::Matrix3d& Sf,
                          double* curvature = nullptr) {
    if (!admissible(p, Ef)) return false;
    for (int t = 0; t < 6; ++t) {
      const int i = kFibreTermRow[t], j = kFibreTermCol[t];
      double w1, w2;
      p.terms[t].derivatives(Ef(i, j), w1, w2);
      const double half = i == j ? 1.0 : 0.5;  // the shear pair appears once in psi
      Sf(i, j) = Sf(j, i) = half * w1;
      if (curvature) curvature[t] = half * w2;
    }
    return true;
  }

  static Eigen::Matrix3d stress(const Parameters& p, const Eigen::Matrix3d& F) {
    Eigen::Matrix3d Sf;
    if (!frameStress(p, frameStrain(p.frame, F), Sf))
      return Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
    return F * (p.frame * Sf * p.frame.transpose());  // P = F B S_f B^T
  }

  // dP = dF S + F dS with dE_f = B^T sym(F^T dF) B, dS_f,t = (w_t'' or w_t''/2) dE_f,t.
  static Eigen::Matrix3d stressDifferential(const Parameters& p, const Eigen::Matrix3d& F,
                                            const Eigen::Matrix3d& dF) {
    Eigen::Matrix3d Sf;
    double curvature[6];
    if (!frameStress(p, frameStrain(p.frame, F), Sf, curvature))
      return Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
    const Eigen::Matrix3d G = F.transpose() * dF;
    const Eigen::Matrix3d dEf = p.frame.transpose() * (0.5 * (G + G.transpose())) * p.frame;
    Eigen::Matrix3d dSf;
    for (int t = 0; t < 6; ++t) {
      const int i = kFibreTermRow[t], j = kFibreTermCol[t];
      dSf(i, j) = dSf(j, i) = curvature[t] * dEf(i, j);
    }
    return dF * (p.frame * Sf * p.frame.transpose()) + F * (p.frame * dSf * p.frame.transpose());
  }
};

// The law `hunter`: Eq. 2.153 with the constants of one material (Table 2.1 by default).
struct HunterLaw : FibreTermLaw<PoleZeroTerm> {
  static constexpr const char* kName = "hunter";
  using Constants = HunterConstants;

  static bool restStressFree(const Constants&) { return true; }  // w'(0) = 0 for every term
  static std::array<PoleZeroTerm, 6> terms(const Constants& c) {
    std::array<PoleZeroTerm, 6> t;
    for (int i = 0; i < 6; ++i) t[i] = {c.k[i], c.a[i], c.b[i]};
    return t;
  }
  static Parameters parameters(const Constants& c, const Eigen::Matrix3d& frame) {
    return {terms(c), orthonormalFrame(frame)};
  }
};

}  // namespace tt
