// The muscle law's stress and tangent through the singular-value frame (teran_muscle_svd_frame.h:
// Eq. 15 and the alpha/beta/eta blocks of Sec. 4.5.1.4 with Eq. 45 of M. Bao, "Derivation of
// Quasistatics and Landmark Optimization for Muscles") against the law's direct derivatives
// (teran_muscle.h, no SVD), on random gradients in the regimes where round-off differs:
// moderate, near-incompressible (large K), large stretch, nearly flat, repeated and nearly
// repeated singular values, an SVD whose U and V are both reflections, and inverted gradients
// (rotationSvd, singular values clamped as inversion handling does).
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

#include "tissue_trainer/core/material/inversion.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/material/teran_muscle_svd_frame.h"
#include "../random_draws.h"

namespace tt {
namespace {

using Frame = TeranMuscleSvdFrame;
using Law = TeranMuscleLaw;

constexpr double kSvdThreshold = 0.25;  // PhysBAM's inversion threshold
constexpr double kRelativeTolerance = 1e-12;

enum class Regime { kModerate, kNearIncompressible, kLargeStretch, kNearlyFlat, kNearRepeated,
                    kRepeated };
const Regime kRegimes[] = {Regime::kModerate, Regime::kNearIncompressible, Regime::kLargeStretch,
                           Regime::kNearlyFlat, Regime::kNearRepeated, Regime::kRepeated};

std::string name(Regime r) {
  switch (r) {
    case Regime::kModerate: return "moderate";
    case Regime::kNearIncompressible: return "near-incompressible";
    case Regime::kLargeStretch: return "large stretch";
    case Regime::kNearlyFlat: return "nearly flat";
    case Regime::kNearRepeated: return "nearly repeated sigma";
    case Regime::kRepeated: return "repeated sigma";
  }
  return "";
}

Eigen::Matrix3d randomOrthogonal(std::mt19937& rng, double det) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix3d X;
  for (int i = 0; i < 9; ++i) X.data()[i] = n(rng);
  Eigen::Matrix3d Q = Eigen::HouseholderQR<Eigen::Matrix3d>(X).householderQ();
  if (Q.determinant() * det < 0) Q.col(0) *= -1.0;
  return Q;
}
Eigen::Matrix3d svdRandomRotation(std::mt19937& rng) { return randomOrthogonal(rng, 1.0); }

Eigen::Vector3d svdRandomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return testutil::drawVector(n, rng).normalized();
}

// R1 diag(s) R2 with random rotations, the right one drawn first (g++'s order of the product
// these tests were written with; random_draws.h).
Eigen::Matrix3d svdRandomRotated(const Eigen::Vector3d& s, std::mt19937& rng) {
  const Eigen::Matrix3d right = svdRandomRotation(rng);
  return svdRandomRotation(rng) * s.asDiagonal() * right;
}

// Singular values (positive, any order) of one regime.
Eigen::Vector3d singularValues(Regime r, std::mt19937& rng) {
  std::uniform_real_distribution<double> log03(-0.3, 0.3), unit(0.0, 1.0);
  const Eigen::Vector3d logs = testutil::drawVector(log03, rng);
  Eigen::Vector3d s(std::exp(logs.x()), std::exp(logs.y()), std::exp(logs.z()));
  switch (r) {
    case Regime::kModerate: break;
    case Regime::kNearIncompressible:  // J = 1 +- 1e-3
      s(2) = (1.0 + (2.0 * unit(rng) - 1.0) * 1e-3) / (s(0) * s(1));
      break;
    case Regime::kLargeStretch: s(0) = 1.8 + 1.2 * unit(rng); break;
    case Regime::kNearlyFlat: s(2) = std::pow(10.0, -3.0 + unit(rng)); break;
    case Regime::kNearRepeated:  // a relative split of 1e-12 to 1e-6
      s(1) = s(0) * (1.0 + std::pow(10.0, -12.0 + 6.0 * unit(rng)));
      if (unit(rng) < 0.3) s(2) = s(0) * (1.0 - std::pow(10.0, -12.0 + 6.0 * unit(rng)));
      break;
    case Regime::kRepeated:  // two or three equal
      s(1) = s(0);
      if (unit(rng) < 0.3) s(2) = s(0);
      break;
  }
  return s;
}

// R1 diag(s) R2 for the regime's singular values, drawn right rotation, s, left rotation (g++'s
// order of the former one-line product).
Eigen::Matrix3d svdRandomGradient(Regime r, std::mt19937& rng) {
  const Eigen::Matrix3d right = svdRandomRotation(rng);
  const Eigen::Vector3d s = singularValues(r, rng);
  return svdRandomRotation(rng) * s.asDiagonal() * right;
}

Law::Parameters randomMuscle(Regime r, int trial, std::mt19937& rng) {
  Law::Parameters p;  // PhysBAM's constants: A 6e4, B 2e4, K 6e4, sigma_max 3e5 Pa
  const double activations[] = {0.0, 0.5, 1.0};
  p.k.activation = activations[trial % 3];
  p.k.deviatoricStretch = (trial / 3) % 2 == 0;
  if (r == Regime::kNearIncompressible) {
    std::uniform_real_distribution<double> u(3.0, 4.0);
    p.k.K = p.k.A * std::pow(10.0, u(rng));
  }
  p.a0 = svdRandomUnit(rng);
  return p;
}

double maxAbs(const Eigen::MatrixXd& a) { return a.lpNorm<Eigen::Infinity>(); }
double svdRelative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return maxAbs(a - b) / maxAbs(b);
}

// What two correct evaluations of P at F may differ by: 1e-12 of |P|, plus the round-off of
// the pressure K ln(J) F^-T, which moves by K |F^-1| dJ / J for a round-off dJ / J of a few
// epsilon in J (det F in the law, sigma1 sigma2 sigma3 here). That second term matters only
// near incompressibility, where K is 1e3-1e4 A and ln J ~ 1e-3 makes |P| small against K.
double stressTolerance(const Law::Parameters& p, const Eigen::Matrix3d& F,
                       const Eigen::Matrix3d& P) {
  return kRelativeTolerance * maxAbs(P) +
         100.0 * std::numeric_limits<double>::epsilon() * p.k.K * maxAbs(F.inverse());
}

struct Worst {
  double value = 0.0;
  void add(double e) { value = std::max(value, e); }
};

constexpr int kTrials = 300;  // per regime, both stretches, activations 0, 0.5 and 1

TEST(TeranMuscleSvdFrame, StressEqualsTheLawsStress) {
  std::mt19937 rng(2001);
  for (Regime r : kRegimes) {
    Worst worst, worstInPressureRoundOff;
    for (int trial = 0; trial < kTrials; ++trial) {
      const Law::Parameters p = randomMuscle(r, trial, rng);
      const Eigen::Matrix3d F = svdRandomGradient(r, rng);
      const RotationSvd svd = rotationSvd(F);
      const Eigen::Matrix3d P = Law::stress(p, F);
      const Eigen::Matrix3d Psvd = Frame::stress(p, svd.U, svd.sigma, svd.V);
      worst.add(svdRelative(Psvd, P));
      worstInPressureRoundOff.add(maxAbs(Psvd - P) / (std::numeric_limits<double>::epsilon() *
                                                      p.k.K * maxAbs(F.inverse())));
      EXPECT_LE(maxAbs(Psvd - P), stressTolerance(p, F, P))
          << name(r) << " sigma " << svd.sigma.transpose() << " deviatoric "
          << p.k.deviatoricStretch;
    }
    std::printf("P: SVD frame vs direct, %s: worst %.2g (%d gradients)\n", name(r).c_str(),
                worst.value, kTrials);
    if (r == Regime::kNearIncompressible)
      std::printf("   largest |P_svd - P| / (epsilon K |F^-1|): %.2g\n",
                  worstInPressureRoundOff.value);
  }
}

// A plain SVD of a gradient with det F > 0 may give U and V that are both reflections; the
// frame form holds for them too (det U det V = +1).
TEST(TeranMuscleSvdFrame, StressEqualsTheLawsStressWithReflectedSingularVectors) {
  std::mt19937 rng(2002);
  Worst worst;
  int reflected = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const Law::Parameters p = randomMuscle(Regime::kModerate, trial, rng);
    const Eigen::Matrix3d right = randomOrthogonal(rng, -1.0);  // g++'s order (random_draws.h)
    const Eigen::Vector3d s = singularValues(Regime::kModerate, rng);
    const Eigen::Matrix3d F = randomOrthogonal(rng, -1.0) * s.asDiagonal() * right;
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
    reflected += U.determinant() < 0.0;
    const Eigen::Matrix3d P = Law::stress(p, F);
    const Eigen::Matrix3d Psvd = Frame::stress(p, U, svd.singularValues(), V);
    worst.add(svdRelative(Psvd, P));
    EXPECT_LE(maxAbs(Psvd - P), stressTolerance(p, F, P));
  }
  EXPECT_GT(reflected, kTrials / 4);
  std::printf("P: SVD frame with U, V both reflections in %d of %d: worst %.2g\n", reflected,
              kTrials, worst.value);
}

// det F < 0: the law is undefined there (NaN), so is the frame form at the signed sigma;
// inversion handling evaluates both at the clamped singular values, F_c = U max(sigma, eps) V^T.
TEST(TeranMuscleSvdFrame, ClampedStressEqualsTheLawsStressOnInvertedGradients) {
  std::mt19937 rng(2003);
  std::uniform_real_distribution<double> u(0.3, 1.6), w(-0.8, -1e-3);
  Worst worst;
  for (int trial = 0; trial < kTrials; ++trial) {
    const Law::Parameters p = randomMuscle(Regime::kModerate, trial, rng);
    const double z = w(rng), y = u(rng), x = u(rng);  // g++'s order (random_draws.h)
    const Eigen::Matrix3d F = svdRandomRotated(Eigen::Vector3d(x, y, z), rng);
    ASSERT_LT(F.determinant(), 0.0);
    const RotationSvd svd = rotationSvd(F);
    ASSERT_LT(svd.sigma(2), 0.0);  // the reflection is on the smallest singular value
    EXPECT_TRUE(Frame::stress(p, svd.U, svd.sigma, svd.V).hasNaN());
    EXPECT_TRUE(Law::stress(p, F).hasNaN());
    bool clamped;
    const Eigen::Matrix3d Fc = clampedGradient(svd, kSvdThreshold, clamped);
    ASSERT_TRUE(clamped);
    const Eigen::Vector3d sc = svd.sigma.cwiseMax(kSvdThreshold);
    const Eigen::Matrix3d P = Law::stress(p, Fc);
    const Eigen::Matrix3d Psvd = Frame::stress(p, svd.U, sc, svd.V);
    worst.add(svdRelative(Psvd, P));
    EXPECT_LE(maxAbs(Psvd - P), stressTolerance(p, Fc, P)) << "sigma " << svd.sigma.transpose();
  }
  std::printf("P: SVD frame (clamped at %.2g) vs direct at F_c, %d inverted gradients: worst "
              "%.2g\n", kSvdThreshold, kTrials, worst.value);
}

TEST(TeranMuscleSvdFrame, TangentEqualsTheLawsTangent) {
  std::mt19937 rng(2004);
  for (Regime r : kRegimes) {
    Worst worst;
    for (int trial = 0; trial < kTrials; ++trial) {
      const Law::Parameters p = randomMuscle(r, trial, rng);
      const Eigen::Matrix3d F = svdRandomGradient(r, rng);
      const RotationSvd svd = rotationSvd(F);
      const double e = svdRelative(Frame::tangent(p, svd.U, svd.sigma, svd.V), Law::tangent(p, F));
      worst.add(e);
      EXPECT_LT(e, kRelativeTolerance) << name(r) << " sigma " << svd.sigma.transpose()
                                      << " deviatoric " << p.k.deviatoricStretch;
    }
    std::printf("dP/dF: SVD frame vs direct, %s: worst %.2g (%d gradients)\n", name(r).c_str(),
                worst.value, kTrials);
  }
}

// The differential along random directions, and on inverted gradients at F_c (the tangent
// inversion handling uses: the law's tangent at F_c).
TEST(TeranMuscleSvdFrame, DifferentialEqualsTheLawsDifferential) {
  std::mt19937 rng(2005);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.3, 1.6), w(-0.8, -1e-3);
  Worst worst, worstInverted;
  for (int trial = 0; trial < kTrials; ++trial) {
    const Law::Parameters p = randomMuscle(Regime::kModerate, trial, rng);
    const bool inverted = trial % 2;
    Eigen::Vector3d s;
    if (inverted) {
      s.z() = w(rng);  // g++'s order (random_draws.h)
      s.y() = u(rng);
      s.x() = u(rng);
    } else {
      s = singularValues(Regime::kModerate, rng);
    }
    const Eigen::Matrix3d F = svdRandomRotated(s, rng);
    const RotationSvd svd = rotationSvd(F);
    bool clamped;
    const Eigen::Matrix3d Fc = inverted ? clampedGradient(svd, kSvdThreshold, clamped) : F;
    const Eigen::Vector3d sc = inverted ? svd.sigma.cwiseMax(kSvdThreshold) : svd.sigma;
    Eigen::Matrix3d dF;
    for (int i = 0; i < 9; ++i) dF.data()[i] = n(rng);
    const double e = svdRelative(Frame::stressDifferential(p, svd.U, sc, svd.V, dF),
                              Law::stressDifferential(p, Fc, dF));
    (inverted ? worstInverted : worst).add(e);
    EXPECT_LT(e, kRelativeTolerance) << "sigma " << svd.sigma.transpose();
  }
  std::printf("dP along random dF: SVD frame vs direct: worst %.2g; inverted (at F_c) %.2g\n",
              worst.value, worstInverted.value);
}

// The isotropic blocks alone: the law's tangent at diag(sigma) without the fibre is zero off
// the blocks, and the blocks are its entries.
TEST(TeranMuscleSvdFrame, IsotropicBlocksAreTheLawsTangentAtDiagonalGradients) {
  std::mt19937 rng(2006);
  Worst worst;
  for (Regime r : kRegimes) {
    for (int trial = 0; trial < 50; ++trial) {
      Law::Parameters p = randomMuscle(r, trial, rng);
      p.k.sigmaMax = 0.0;
      const Eigen::Vector3d s = singularValues(r, rng);
      const Matrix9d law = Law::tangent(p, Eigen::Matrix3d(s.asDiagonal()));
      const Frame::IsotropicBlocks m = Frame::isotropicBlocks(p.k, s);
      Matrix9d blocks = Matrix9d::Zero();
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          if (i == j) {
            for (int l = 0; l < 3; ++l) blocks(4 * i, 4 * l) = m.diagonal(i, l);
          } else {
            blocks(i + 3 * j, i + 3 * j) = m.alpha[i][j];
            blocks(i + 3 * j, j + 3 * i) = m.beta[i][j];
          }
        }
      const double e = svdRelative(blocks, law);
      worst.add(e);
      EXPECT_LT(e, kRelativeTolerance) << name(r) << " sigma " << s.transpose();
    }
  }
  std::printf("alpha/beta/eta blocks vs the law's isotropic tangent at diag(sigma): worst %.2g\n",
              worst.value);
}

}  // namespace
}  // namespace tt
