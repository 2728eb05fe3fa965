// The Hunter pole-zero law ("Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.8.1,
// Eq. 2.153, Table 2.1) and its pole-free polynomial substitute (Sec. 2.9.2). The
// finite-difference, frame-indifference and rest checks of both laws are in the conformance
// suite (test_law_conformance.cpp); here: the uniaxial curves and shear energies against
// reference values computed independently of this code, the stress convention for the shear
// terms, the fibre frame, the poles, and the substitute against the law.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "../model_test_util.h"
#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/hunter_polynomial.h"

namespace tt {
namespace {

using testutil::frameFrom;
using testutil::randomRotation;
using testutil::randomUnit;

const char* const kAxisName[3] = {"fibre", "sheet", "sheet-normal"};

// Frames to test in: the identity and a random rotation (the law works in the frame).
std::vector<Eigen::Matrix3d> frames() {
  std::mt19937 rng(41);
  return {Eigen::Matrix3d::Identity(), randomRotation(rng)};
}

// F = I + (lambda - 1) b_l b_l^T: a stretch lambda along axis l of frame B, lateral stretches 1.
Eigen::Matrix3d stretchAlong(const Eigen::Matrix3d& B, int l, double lambda) {
  return Eigen::Matrix3d::Identity() + (lambda - 1.0) * B.col(l) * B.col(l).transpose();
}

// Uniaxial stress along each axis with the lateral strains held at zero (for this law the
// lateral stresses then vanish too, since psi is a sum of one-component functions). Reference
// values in kPa: S_ll = w_ll'(E_ll) and P_ll = lambda S_ll for Table 2.1, from a separate
// double-precision evaluation of Eq. 2.153 checked against complex-step derivatives.
struct UniaxialReference {
  int axis;
  double lambda, S, P;  // kPa
};
const UniaxialReference kUniaxial[] = {
    {0, 1.05, 0.704274, 0.739488},    {0, 1.10, 1.80745, 1.98819},
    {0, 1.15, 3.84798, 4.42518},      {0, 1.20, 9.05951, 10.8714},
    {1, 1.05, 0.0843581, 0.088576},   {1, 1.10, 0.303466, 0.333813},
    {1, 1.15, 0.931835, 1.07161},     {1, 1.20, 3.10135, 3.72162},
    {2, 1.05, 0.0322877, 0.033902},   {2, 1.10, 0.0684514, 0.0752966},
    {2, 1.15, 0.109258, 0.125647},    {2, 1.20, 0.155747, 0.186897},
};

template <class Law>
void expectUniaxialReference(const typename Law::Constants& constants) {
  for (const Eigen::Matrix3d& B : frames()) {
    const auto p = Law::parameters(constants, B);
    std::printf("%s  axis          lambda  S ref (kPa)  S law (kPa)  P ref (kPa)  P law (kPa)\n",
                Law::kName);
    for (const UniaxialReference& r : kUniaxial) {
      const Eigen::Matrix3d F = stretchAlong(B, r.axis, r.lambda);
      const Eigen::Matrix3d P = Law::stress(p, F);
      const Eigen::Matrix3d Pf = B.transpose() * P * B;                    // P in the frame
      const Eigen::Matrix3d Sf = B.transpose() * F.inverse() * P * B;      // S = F^-1 P
      const double S = 1e-3 * Sf(r.axis, r.axis), Pll = 1e-3 * Pf(r.axis, r.axis);
      std::printf("%s  %-12s  %.2f    %-11.6g  %-11.6g  %-11.6g  %-11.6g\n", Law::kName,
                  kAxisName[r.axis], r.lambda, r.S, S, r.P, Pll);
      EXPECT_NEAR(S, r.S, 1e-5 * r.S) << kAxisName[r.axis] << " lambda " << r.lambda;
      EXPECT_NEAR(Pll, r.P, 1e-5 * r.P) << kAxisName[r.axis] << " lambda " << r.lambda;
      // Nothing else: no lateral stress, no shear.
      Eigen::Matrix3d rest = Sf;
      rest(r.axis, r.axis) = 0.0;
      EXPECT_LT(rest.lpNorm<Eigen::Infinity>(), 1e-12 * Sf.lpNorm<Eigen::Infinity>());
    }
  }
}

TEST(HunterLaw, UniaxialCurvesMatchTheReferenceValues) {
  expectUniaxialReference<HunterLaw>(HunterConstants::table21());
}

// Simple shear in the three planes of Sec. 2.8.1, F = I + gamma e_s (x) e_N in the frame:
// E_NN = gamma^2 / 2 and E_sN = gamma / 2, so W = w_NN(gamma^2 / 2) + w_sN(gamma / 2).
// Reference energies in kPa at gamma = 0.1 ... 0.5 (same independent evaluation as above).
TEST(HunterLaw, ShearEnergiesMatchTheReferenceValues) {
  struct Plane {
    const char* name;
    int moved, normal;  // F = I + gamma e_moved (x) e_normal
    double W[5];
  };
  const Plane planes[] = {
      {"fn", 2, 0, {0.00553738, 0.0275352, 0.0795931, 0.186411, 0.394093}},
      {"sf", 0, 1, {0.00540393, 0.0253468, 0.0680243, 0.14735, 0.289005}},
      {"ns", 1, 2, {0.00358472, 0.0163097, 0.042166, 0.0870176, 0.159538}},
  };
  for (const Eigen::Matrix3d& B : frames()) {
    const auto p = HunterLaw::parameters(HunterConstants::table21(), B);
    for (const Plane& plane : planes)
      for (int g = 0; g < 5; ++g) {
        const double gamma = 0.1 * (g + 1);
        const Eigen::Matrix3d F = Eigen::Matrix3d::Identity() +
                                  gamma * B.col(plane.moved) * B.col(plane.normal).transpose();
        const double W = 1e-3 * HunterLaw::energy(p, F);
        std::printf("hunter shear %s  gamma %.1f  W ref %-10.6g  W law %-10.6g kPa\n",
                    plane.name, gamma, plane.W[g], W);
        EXPECT_NEAR(W, plane.W[g], 1e-5 * plane.W[g]) << plane.name << " gamma " << gamma;
      }
  }
}

// Each shear pair appears once in Eq. 2.153, so S_12 = S_21 = w_12'(E_12) / 2: the derivative
// of W with respect to E_12 with E_21 tied to it is 2 S_12, and P = F S is d psi / dF (the
// conformance suite checks the latter by finite differences on random states).
TEST(HunterLaw, ShearStressIsHalfTheTiedDerivative) {
  const auto p = HunterLaw::parameters(HunterConstants::table21(), Eigen::Matrix3d::Identity());
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  E(0, 0) = 0.08, E(1, 1) = 0.05, E(2, 2) = -0.03;
  E(0, 1) = E(1, 0) = 0.11;
  E(0, 2) = E(2, 0) = -0.07;
  E(1, 2) = E(2, 1) = 0.09;
  // F with F^T F = I + 2E (the symmetric square root).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(Eigen::Matrix3d::Identity() + 2 * E);
  const Eigen::Matrix3d F =
      eig.eigenvectors() * eig.eigenvalues().cwiseSqrt().asDiagonal() * eig.eigenvectors().transpose();
  const Eigen::Matrix3d S = F.inverse() * HunterLaw::stress(p, F);
  const auto W = [&](const Eigen::Matrix3d& strain) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> e(Eigen::Matrix3d::Identity() + 2 * strain);
    const Eigen::Matrix3d G =
        e.eigenvectors() * e.eigenvalues().cwiseSqrt().asDiagonal() * e.eigenvectors().transpose();
    return HunterLaw::energy(p, G);
  };
  const double h = 1e-6;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      Eigen::Matrix3d Ep = E, Em = E;
      Ep(i, j) += h, Em(i, j) -= h;
      if (i != j) Ep(j, i) += h, Em(j, i) -= h;
      const double tied = (W(Ep) - W(Em)) / (2 * h);
      EXPECT_NEAR(S(i, j), (i == j ? 1.0 : 0.5) * tied, 1e-6 * std::abs(tied)) << i << j;
      EXPECT_NEAR(S(i, j), S(j, i), 1e-12 * std::abs(S(i, j)));
    }
}

// The law reads strains in the element's frame: turning the frame and the deformation
// together leaves the energy unchanged, and a frame that is not orthonormal is made so
// (fibre column kept, sheet column orthogonalised).
TEST(HunterLaw, WorksInTheElementsFibreFrame) {
  std::mt19937 rng(42);
  const HunterConstants c = HunterConstants::table21();
  const auto identity = HunterLaw::parameters(c, Eigen::Matrix3d::Identity());
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Matrix3d B = frameFrom(randomUnit(rng));
    Eigen::Matrix3d Floc = Eigen::Matrix3d::Identity();
    std::uniform_real_distribution<double> u(-0.08, 0.08);
    for (int i = 0; i < 9; ++i) Floc.data()[i] += u(rng);
    const Eigen::Matrix3d F = B * Floc * B.transpose();
    const double W = HunterLaw::energy(identity, Floc);
    EXPECT_NEAR(HunterLaw::energy(HunterLaw::parameters(c, B), F), W, 1e-12 * W);
    Eigen::Matrix3d skewed = B;
    skewed.col(0) *= 3.0;
    skewed.col(1) = 0.5 * B.col(1) + 0.7 * B.col(0);
    skewed.col(2) = -2.0 * B.col(2) + 0.3 * B.col(1);
    EXPECT_NEAR(HunterLaw::energy(HunterLaw::parameters(c, skewed), F), W, 1e-12 * W);
  }
}

// Poles at E_ll = a_ll, i.e. lambda = sqrt(1 + 2 a_ll) = 1.27906 (fibre), 1.36308 (sheet),
// 1.75328 (sheet-normal): the energy rises without bound below the pole and is infinite at
// and beyond it, where the stress and its differential are NaN (never a finite wrong value).
TEST(HunterLaw, PolesGiveAnInfiniteEnergyAndNoFiniteStress) {
  const HunterConstants c = HunterConstants::table21();
  const double poles[3] = {1.27906, 1.36308, 1.75328};
  for (const Eigen::Matrix3d& B : frames()) {
    const auto p = HunterLaw::parameters(c, B);
    for (int l = 0; l < 3; ++l) {
      const double pole = std::sqrt(1.0 + 2.0 * c.a[l]);
      EXPECT_NEAR(pole, poles[l], 1e-5);
      const double below = HunterLaw::energy(p, stretchAlong(B, l, pole - 1e-3));
      const double closer = HunterLaw::energy(p, stretchAlong(B, l, pole - 1e-5));
      EXPECT_TRUE(std::isfinite(closer));
      EXPECT_GT(closer, below) << kAxisName[l];
      for (double lambda : {pole + 1e-9, pole + 0.05, pole + 1.0}) {
        const Eigen::Matrix3d F = stretchAlong(B, l, lambda);
        EXPECT_EQ(HunterLaw::energy(p, F), std::numeric_limits<double>::infinity())
            << kAxisName[l] << " lambda " << lambda;
        EXPECT_TRUE(HunterLaw::stress(p, F).array().isNaN().all());
        EXPECT_TRUE(HunterLaw::stressDifferential(p, F, Eigen::Matrix3d::Identity())
                        .array().isNaN().all());
      }
    }
    // At the pole itself (e = a) the term has no value either.
    EXPECT_FALSE(p.terms[0].admissible(c.a[0]));
    EXPECT_TRUE(p.terms[0].admissible(std::nextafter(c.a[0], 0.0)));
    // A shear term's pole: E_12 = 0.75 > a_12 = 0.731 with small normal strains.
    Eigen::Matrix3d Floc = Eigen::Matrix3d::Identity();
    Floc(0, 0) = 0.9, Floc(1, 1) = 0.85;
    Floc(0, 1) = Floc(1, 0) = 0.85;  // E_12 = 0.744, E_11 = 0.266, E_22 = 0.2225
    const Eigen::Matrix3d Ef = 0.5 * (Floc.transpose() * Floc - Eigen::Matrix3d::Identity());
    ASSERT_GT(Ef(0, 1), c.a[3]);
    ASSERT_LT(Ef(0, 0), c.a[0]);
    ASSERT_LT(Ef(1, 1), c.a[1]);
    EXPECT_FALSE(std::isfinite(HunterLaw::energy(p, B * Floc * B.transpose())));
  }
}

// As printed, the shear terms k E_ij^2 / |a_ij - E_ij|^b_ij are not even in E_ij: a negative
// shear strain is softer and meets no pole. Reflecting the sheet axis (a symmetry of an
// orthotropic material) turns E_12 into -E_12, so this law is not orthotropic; the law is kept
// as printed (the reference values above use positive shears only), and this pins the fact.
TEST(HunterLaw, PrintedShearTermsAreNotEvenInTheShearStrain) {
  const auto p = HunterLaw::parameters(HunterConstants::table21(), Eigen::Matrix3d::Identity());
  const PoleZeroTerm& w12 = p.terms[3];
  EXPECT_NEAR(1e-3 * w12.value(0.3), 0.484494, 1e-6);   // k 0.09 / 0.431^2 (kPa)
  EXPECT_NEAR(1e-3 * w12.value(-0.3), 0.0846691, 1e-7);  // k 0.09 / 1.031^2
  EXPECT_TRUE(w12.admissible(-10.0));
  // The same through F: the sheet axis reflected.
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 1) = 0.25;
  const Eigen::Matrix3d R = Eigen::Vector3d(1.0, -1.0, 1.0).asDiagonal();
  const double W = HunterLaw::energy(p, F), reflected = HunterLaw::energy(p, R * F * R);
  EXPECT_GT(W, 1.5 * reflected);
}

// --- The pole-free substitute (Sec. 2.9.2) ---

// Below the switch strain of every term it is the pole-zero law, bitwise (the same code).
TEST(HunterPolynomialLaw, EqualsThePoleZeroLawBelowTheSwitchStrain) {
  std::mt19937 rng(43);
  std::normal_distribution<double> n(0.0, 0.12);
  const HunterPolynomialLaw::Constants c;  // Table 2.1, s = 0.9, n = 3
  int compared = 0;
  for (int trial = 0; trial < 400 && compared < 100; ++trial) {
    const Eigen::Matrix3d B = frameFrom(randomUnit(rng));
    const auto exact = HunterLaw::parameters(c.hunter, B);
    const auto substitute = HunterPolynomialLaw::parameters(c, B);
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    for (int i = 0; i < 9; ++i) F.data()[i] += n(rng);
    const Eigen::Matrix3d Ef = HunterLaw::frameStrain(B, F);
    bool below = true;
    for (int t = 0; t < 6; ++t)
      below = below && Ef(kFibreTermRow[t], kFibreTermCol[t]) <= c.switchFraction * c.hunter.a[t];
    if (!below || F.determinant() < 0.3) continue;
    ++compared;
    const Eigen::Matrix3d dF = Eigen::Matrix3d::Random();
    EXPECT_EQ(HunterPolynomialLaw::energy(substitute, F), HunterLaw::energy(exact, F));
    EXPECT_EQ(HunterPolynomialLaw::stress(substitute, F), HunterLaw::stress(exact, F));
    EXPECT_EQ(HunterPolynomialLaw::stressDifferential(substitute, F, dF),
              HunterLaw::stressDifferential(exact, F, dF));
  }
  EXPECT_EQ(compared, 100);
  // So its uniaxial curves to 20 % stretch are the law's: the switch stretches
  // sqrt(1 + 2 s a_ll) are 1.2539 (fibre), 1.3296 (sheet), 1.6957 (sheet-normal).
  expectUniaxialReference<HunterPolynomialLaw>(c);
}

// Each term: the Taylor coefficients are the derivatives at e_s (c_0, c_1, 2 c_2 against the
// closed forms, 6 c_3 against a difference of w''), value, slope and curvature are
// continuous at the switch, the polynomial approaches w as the degree rises inside the
// pole's radius, and beyond the switch, at the pole and past it the substitute is finite
// and rising with a rising slope.
TEST(HunterPolynomialLaw, TermsContinueThePoleZeroTermsSmoothlyAndWithoutAPole) {
  const HunterConstants table = HunterConstants::table21();
  const std::array<PoleZeroTerm, 6> laws = HunterLaw::terms(table);
  for (int t = 0; t < 6; ++t) {
    SCOPED_TRACE(kFibreTermLabel[t]);
    const PoleZeroTerm& w = laws[t];
    const double es = 0.9 * w.a, d = w.a - es;
    double w1, w2;
    w.derivatives(es, w1, w2);
    for (int degree = 2; degree <= PoleFreeTerm::kMaxDegree; ++degree) {
      const PoleFreeTerm s = PoleFreeTerm::make(w, 0.9, degree);
      EXPECT_NEAR(s.c[0], w.value(es), 1e-13 * w.value(es));
      EXPECT_NEAR(s.c[1], w1, 1e-13 * w1);
      EXPECT_NEAR(2.0 * s.c[2], w2, 1e-13 * w2);
      if (degree >= 3) {
        const double h = 1e-7 * d;
        double a1, a2, b1, b2;
        w.derivatives(es + h, a1, a2);
        w.derivatives(es - h, b1, b2);
        const double w3 = (a2 - b2) / (2 * h);
        EXPECT_NEAR(6.0 * s.c[3], w3, 1e-6 * w3);
      }
      // Continuity at the switch (one-sided values a hair apart).
      const double eps = 1e-9 * w.a;
      double l1, l2, r1, r2;
      s.derivatives(es - eps, l1, l2);
      s.derivatives(es + eps, r1, r2);
      EXPECT_NEAR(s.value(es + eps), s.value(es - eps), 1e-7 * s.value(es));
      EXPECT_NEAR(r1, l1, 1e-7 * std::abs(l1));
      EXPECT_NEAR(r2, l2, 1e-6 * std::abs(l2));
      // Finite and rising (with a rising slope) to well past the pole.
      double last = s.value(es), lastSlope = w1;
      for (double e : {es + 0.5 * d, w.a, w.a + 0.1, w.a + 1.0, w.a + 10.0}) {
        double s1, s2;
        s.derivatives(e, s1, s2);
        EXPECT_TRUE(std::isfinite(s.value(e)) && std::isfinite(s1) && std::isfinite(s2)) << e;
        EXPECT_GT(s.value(e), last) << e;
        EXPECT_GT(s1, lastSlope) << e;
        EXPECT_GT(s2, 0.0) << e;
        last = s.value(e), lastSlope = s1;
      }
    }
    // Inside the Taylor series' radius (d, the distance to the pole) a higher degree is closer.
    const double e = es + 0.4 * d;
    double previous = std::numeric_limits<double>::infinity();
    for (int degree = 2; degree <= PoleFreeTerm::kMaxDegree; ++degree) {
      const double error = std::abs(PoleFreeTerm::make(w, 0.9, degree).value(e) - w.value(e));
      EXPECT_LT(error, previous) << "degree " << degree;
      previous = error;
    }
  }
}

// A uniaxial stretch past the fibre pole: the law has no state there, the substitute a finite
// stress that keeps rising; both agree up to the switch stretch.
TEST(HunterPolynomialLaw, UniaxialStretchPastThePoleStaysFinite) {
  const HunterPolynomialLaw::Constants c;
  const Eigen::Matrix3d B = frames()[1];
  const auto exact = HunterLaw::parameters(c.hunter, B);
  const auto substitute = HunterPolynomialLaw::parameters(c, B);
  const double switchStretch = std::sqrt(1.0 + 2.0 * c.switchFraction * c.hunter.a[0]);
  double last = 0.0;
  for (double lambda = 1.0; lambda <= 1.6; lambda += 0.01) {
    const Eigen::Matrix3d F = stretchAlong(B, 0, lambda);
    const double P = B.col(0).dot(HunterPolynomialLaw::stress(substitute, F) * B.col(0));
    ASSERT_TRUE(std::isfinite(P)) << lambda;
    if (lambda > 1.0) EXPECT_GT(P, last) << lambda;
    last = P;
    if (lambda <= switchStretch)
      EXPECT_EQ(P, B.col(0).dot(HunterLaw::stress(exact, F) * B.col(0))) << lambda;
    else if (lambda >= std::sqrt(1.0 + 2.0 * c.hunter.a[0]))
      EXPECT_FALSE(std::isfinite(HunterLaw::energy(exact, F))) << lambda;
  }
}

}  // namespace
}  // namespace tt
