#pragma once
// The pole-free substitute of the Hunter pole-zero law ("Adamss: Advanced Anisotropic
// Mass-Spring System", Sec. 2.9.2: a law with a pole is replaced by a polynomial, which has
// none, so a time step that overshoots the pole still gets a meaningful stress). The chapter
// gives no formula for the substitute; this one keeps Eq. 2.153 where its strains are valid
// and is a polynomial where the pole would be. Each term w(e) = k e^2 / (a - e)^b
// (material/hunter.h) is replaced beyond its switch strain e_s = s a (0 < s < 1) by its Taylor
// polynomial of degree n at e_s:
//   w~(e) = w(e)                                   for e <= e_s,
//   w~(e) = sum_{m=0..n} w^(m)(e_s) (e - e_s)^m / m!   for e > e_s,
// so w~ has n continuous derivatives at e_s, equals the pole-zero law below the switch
// (compression and negative shear included), and is finite at and beyond the pole. With
// g(e) = (a - e)^-b, g^(j) = b (b + 1) ... (b + j - 1) (a - e)^(-b-j) and Leibniz's rule,
//   w^(m) = k [e^2 g^(m) + 2 m e g^(m-1) + m (m - 1) g^(m-2)],
// which is positive at e_s > 0 for every m when k > 0 and b >= 0: beyond the switch w~ keeps
// rising with a rising slope, like the law it replaces.
#include <array>
#include <cmath>

#include "tissue_trainer/core/material/hunter.h"

namespace tt {

// One term of the substitute: the pole-zero term up to eSwitch, its Taylor polynomial beyond.
struct PoleFreeTerm {
  static constexpr int kMaxDegree = 6;

  PoleZeroTerm law;
  double eSwitch = 0.0;
  int degree = 3;
  std::array<double, kMaxDegree + 1> c{};  // c_m = w^(m)(e_s) / m!

  static PoleFreeTerm make(const PoleZeroTerm& law, double switchFraction, int degree) {
    PoleFreeTerm t;
    t.law = law;
    t.eSwitch = switchFraction * law.a;
    t.degree = degree;
    const double e = t.eSwitch, d = law.a - e;
    // g^(j)(e_s) for j = 0..degree.
    std::array<double, kMaxDegree + 1> g{};
    g[0] = std::pow(d, -law.b);
    for (int j = 1; j <= degree; ++j) g[j] = g[j - 1] * (law.b + j - 1) / d;
    double factorial = 1.0;
    for (int m = 0; m <= degree; ++m) {
      if (m > 0) factorial *= m;
      double wm = e * e * g[m];
      if (m >= 1) wm += 2.0 * m * e * g[m - 1];
      if (m >= 2) wm += m * (m - 1.0) * g[m - 2];
      t.c[m] = law.k * wm / factorial;
    }
    return t;
  }

  bool admissible(double) const { return true; }
  double value(double e) const {
    if (e <= eSwitch) return law.value(e);
    const double x = e - eSwitch;
    double w = c[degree];
    for (int m = degree - 1; m >= 0; --m) w = w * x + c[m];
    return w;
  }
  void derivatives(double e, double& first, double& second) const {
    if (e <= eSwitch) return law.derivatives(e, first, second);
    const double x = e - eSwitch;
    first = degree * c[degree];
    second = degree * (degree - 1.0) * c[degree];
    for (int m = degree - 1; m >= 1; --m) {
      first = first * x + m * c[m];
      if (m >= 2) second = second * x + m * (m - 1.0) * c[m];
    }
  }
};

// The law `hunter_polynomial`: the Hunter constants, the switch fraction s and the degree n.
struct HunterPolynomialLaw : FibreTermLaw<PoleFreeTerm> {
  static constexpr const char* kName = "hunter_polynomial";

  struct Constants {
    HunterConstants hunter = HunterConstants::table21();
    double switchFraction = 0.9;  // s in (0, 1)
    int degree = 3;               // n in [2, PoleFreeTerm::kMaxDegree]
  };

  static bool restStressFree(const Constants&) { return true; }  // e_s > 0: w~ = w near 0
  static Parameters parameters(const Constants& c, const Eigen::Matrix3d& frame) {
    Parameters p;
    const std::array<PoleZeroTerm, 6> laws = HunterLaw::terms(c.hunter);
    for (int t = 0; t < 6; ++t) p.terms[t] = PoleFreeTerm::make(laws[t], c.switchFraction, c.degree);
    p.frame = orthonormalFrame(frame);
    return p;
  }
};

}  // namespace tt
