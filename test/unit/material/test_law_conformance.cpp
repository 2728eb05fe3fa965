// The conformance suite of the material laws: the same checks on every law in LawTypes
// (a new law adds itself there). Point checks of psi, P and dP against each other by finite
// differences, frame indifference, isotropy where claimed, zero stress at rest where the law
// has it, the rotation-only SVD, inversion handling and the PSD projection.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>
#include <type_traits>

#include "../model_test_util.h"
#include "tissue_trainer/core/material/guccione.h"
#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/hunter_polynomial.h"
#include "tissue_trainer/core/material/inversion.h"
#include "tissue_trainer/core/material/law_point.h"
#include "tissue_trainer/core/material/neo_hookean.h"
#include "tissue_trainer/core/material/psd_projection.h"
#include "tissue_trainer/core/material/stvk.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/material/volume.h"

namespace tt {
namespace {

// Sample constants of each law: soft-tissue magnitudes (Pa).
template <class Law>
typename Law::Constants sampleConstants();
template <>
StvkLaw::Constants sampleConstants<StvkLaw>() {
  return StvkLaw::constants(Material::transverselyIsotropic(3e4, 0.3, 1.2e5, 0.35, 1000.0));
}
template <>
NeoHookeanLaw::Constants sampleConstants<NeoHookeanLaw>() {
  return NeoHookeanLaw::constants(Material::isotropic(1e4, 0.45, 1000.0));
}
template <>
VolumeLaw::Constants sampleConstants<VolumeLaw>() {
  return {5e3, 1.0};
}
template <>
HunterLaw::Constants sampleConstants<HunterLaw>() {
  return HunterConstants::table21();
}
template <>
GuccioneLaw::Constants sampleConstants<GuccioneLaw>() {
  return {2000.0, 8.0, 2.0, 4.0, 5e4};  // the benchmark's beam, kappa = 25 C
}
template <>
HunterPolynomialLaw::Constants sampleConstants<HunterPolynomialLaw>() {
  return {};  // Table 2.1, switch at 0.9 of each pole, degree 3
}
// The muscle law in its option combinations: each fibre stretch, active and passive.
template <bool Deviatoric, bool Active>
struct TeranMuscle : TeranMuscleLaw {};
template <class Law>
struct IsTeranMuscle : std::false_type {};
template <bool D, bool A>
struct IsTeranMuscle<TeranMuscle<D, A>> : std::true_type {};
template <class Law>
typename Law::Constants sampleTeranConstants() {
  TeranMuscleLaw::Constants k;  // PhysBAM's defaults
  k.deviatoricStretch = std::is_same_v<Law, TeranMuscle<true, true>> ||
                        std::is_same_v<Law, TeranMuscle<true, false>>;
  k.activation = std::is_same_v<Law, TeranMuscle<true, true>> ||
                         std::is_same_v<Law, TeranMuscle<false, true>>
                     ? 0.6
                     : 0.0;
  return k;
}
template <>
TeranMuscleLaw::Constants sampleConstants<TeranMuscle<true, true>>() {
  return sampleTeranConstants<TeranMuscle<true, true>>();
}
template <>
TeranMuscleLaw::Constants sampleConstants<TeranMuscle<false, true>>() {
  return sampleTeranConstants<TeranMuscle<false, true>>();
}
template <>
TeranMuscleLaw::Constants sampleConstants<TeranMuscle<true, false>>() {
  return sampleTeranConstants<TeranMuscle<true, false>>();
}
template <>
TeranMuscleLaw::Constants sampleConstants<TeranMuscle<false, false>>() {
  return sampleTeranConstants<TeranMuscle<false, false>>();
}

// The energy density at rest: 0 except for the muscle law, which keeps Eq. 10's 3 (A + B).
template <class Law>
double restEnergy(const typename Law::Constants& k) {
  if constexpr (IsTeranMuscle<Law>::value) return Law::restEnergy(k);
  return 0.0;
}

Eigen::Matrix3d randomGradient(std::mt19937& rng, double amplitude) {
  std::normal_distribution<double> n(0.0, 1.0);
  for (;;) {
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    for (int i = 0; i < 9; ++i) F.data()[i] += amplitude * n(rng);
    if (F.determinant() > 0.3) return F;
  }
}

// The states a law is checked at: every state for most laws; for the pole-zero law, states
// whose fibre-frame strains stay below 0.9 of each pole (beyond a pole it has no state, and
// the substitute hunter_polynomial is checked across its switch and past the poles).
template <class Law>
bool checkedState(const typename Law::Parameters& p, const Eigen::Matrix3d& F) {
  if constexpr (std::is_same_v<Law, HunterLaw>) {
    const Eigen::Matrix3d Ef = HunterLaw::frameStrain(p.frame, F);
    for (int t = 0; t < 6; ++t)
      if (!(Ef(kFibreTermRow[t], kFibreTermCol[t]) < 0.9 * p.terms[t].a)) return false;
  }
  return true;
}

template <class Law>
Eigen::Matrix3d sampleGradient(std::mt19937& rng, const typename Law::Parameters& p,
                               double amplitude) {
  for (;;) {
    const Eigen::Matrix3d F = randomGradient(rng, amplitude);
    if (checkedState<Law>(p, F)) return F;
  }
}

// Central differences of the energy density: the stress a law must give.
template <class Law>
Eigen::Matrix3d energyGradient(const typename Law::Parameters& p, const Eigen::Matrix3d& F) {
  Eigen::Matrix3d fd;
  const double h = 1e-6;
  for (int i = 0; i < 9; ++i) {
    Eigen::Matrix3d Fp = F, Fm = F;
    Fp.data()[i] += h;
    Fm.data()[i] -= h;
    fd.data()[i] = (Law::energy(p, Fp) - Law::energy(p, Fm)) / (2 * h);
  }
  return fd;
}

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(b.lpNorm<Eigen::Infinity>(), 1e-300);
}

template <class Law>
class LawConformance : public ::testing::Test {
 protected:
  typename Law::Parameters params(std::mt19937& rng) const {
    return Law::parameters(sampleConstants<Law>(), testutil::frameFrom(testutil::randomUnit(rng)));
  }
};

using LawTypes =
    ::testing::Types<StvkLaw, NeoHookeanLaw, VolumeLaw, HunterLaw, HunterPolynomialLaw,
                     GuccioneLaw, TeranMuscle<true, true>, TeranMuscle<false, true>, TeranMuscle<true, false>,
                     TeranMuscle<false, false>>;
TYPED_TEST_SUITE(LawConformance, LawTypes);

TYPED_TEST(LawConformance, StressIsTheEnergyGradient) {
  using Law = TypeParam;
  std::mt19937 rng(11);
  double worst = 0.0;
  for (int trial = 0; trial < 50; ++trial) {
    const auto p = this->params(rng);
    const Eigen::Matrix3d F = sampleGradient<Law>(rng, p, 0.25);
    worst = std::max(worst, relative(energyGradient<Law>(p, F), Law::stress(p, F)));
  }
  EXPECT_LT(worst, 1e-6) << Law::kName;
}

TYPED_TEST(LawConformance, DifferentialIsTheStressDerivativeAndSymmetric) {
  using Law = TypeParam;
  std::mt19937 rng(12);
  double worst = 0.0, asymmetry = 0.0;
  for (int trial = 0; trial < 50; ++trial) {
    const auto p = this->params(rng);
    const Eigen::Matrix3d F = sampleGradient<Law>(rng, p, 0.25);
    const Eigen::Matrix3d dF = randomGradient(rng, 1.0) - Eigen::Matrix3d::Identity();
    const double h = 1e-6;
    const Eigen::Matrix3d fd =
        (Law::stress(p, F + h * dF) - Law::stress(p, F - h * dF)) / (2 * h);
    worst = std::max(worst, relative(fd, Law::stressDifferential(p, F, dF)));
    const Matrix9d A = lawTangent<Law>(p, F);
    asymmetry = std::max(asymmetry, relative(A.transpose(), A));
  }
  EXPECT_LT(worst, 1e-6) << Law::kName;
  EXPECT_LT(asymmetry, 1e-12) << Law::kName << ": the tangent of a hyperelastic law is symmetric";
}

TYPED_TEST(LawConformance, FrameIndifferentAndIsotropicWhereClaimed) {
  using Law = TypeParam;
  std::mt19937 rng(13);
  for (int trial = 0; trial < 20; ++trial) {
    const auto p = this->params(rng);
    const Eigen::Matrix3d F = sampleGradient<Law>(rng, p, 0.3);
    const Eigen::Matrix3d Q = testutil::randomRotation(rng);
    EXPECT_NEAR(Law::energy(p, Q * F), Law::energy(p, F), 1e-10 * std::abs(Law::energy(p, F)));
    EXPECT_LT(relative(Law::stress(p, Q * F), Q * Law::stress(p, F)), 1e-10);
    if (Law::kIsotropic) {
      EXPECT_NEAR(Law::energy(p, F * Q), Law::energy(p, F), 1e-10 * std::abs(Law::energy(p, F)));
      EXPECT_LT(relative(Law::stress(p, F * Q), Law::stress(p, F) * Q), 1e-10);
    }
  }
}

TYPED_TEST(LawConformance, NoStressAtRestWhereTheLawHasNone) {
  using Law = TypeParam;
  std::mt19937 rng(14);
  const auto k = sampleConstants<Law>();
  if constexpr (IsTeranMuscle<Law>::value) {
    if (k.activation > 0.0) {  // an active muscle pulls at rest: t_a(1) = 1
      EXPECT_FALSE(Law::restStressFree(k));
      const auto p = this->params(rng);
      Eigen::Matrix3d expected = p.a0 * p.a0.transpose();
      if (k.deviatoricStretch) expected -= Eigen::Matrix3d::Identity() / 3.0;
      expected *= k.sigmaMax * k.activation;
      EXPECT_LT(relative(Law::stress(p, Eigen::Matrix3d::Identity()), expected), 1e-12);
      return;
    }
  }
  ASSERT_TRUE(Law::restStressFree(k));
  const auto p = this->params(rng);
  EXPECT_NEAR(Law::energy(p, Eigen::Matrix3d::Identity()), restEnergy<Law>(k),
              1e-15 * restEnergy<Law>(k));
  EXPECT_LT(Law::stress(p, Eigen::Matrix3d::Identity()).norm(), 1e-9);
}

TYPED_TEST(LawConformance, ProjectedTangentHasNoNegativeEigenvalue) {
  using Law = TypeParam;
  std::mt19937 rng(15);
  int indefinite = 0;
  LawOptions options;
  options.psdProjection = true;
  options.inversionThreshold = 0.05;
  for (int trial = 0; trial < 50; ++trial) {
    const auto p = this->params(rng);
    const Eigen::Matrix3d F = sampleGradient<Law>(rng, p, 0.6);  // large: indefinite tangents occur
    LawPoint point = lawPoint(F, options);
    const Matrix9d A = lawTangent<Law>(p, point.F);
    indefinite += Eigen::SelfAdjointEigenSolver<Matrix9d>(0.5 * (A + A.transpose()))
                      .eigenvalues()
                      .minCoeff() < 0.0;
    const Matrix9d projected = pointTangent<Law>(p, point, options);
    const Eigen::VectorXd lambda =
        Eigen::SelfAdjointEigenSolver<Matrix9d>(projected).eigenvalues();
    EXPECT_GE(lambda.minCoeff(), -1e-9 * lambda.cwiseAbs().maxCoeff()) << Law::kName;
    if (Law::kIsotropic) {  // the block form and the full eigenvalue clamp agree
      Matrix9d full = A;
      projectPsd(full);
      EXPECT_LT(relative(projected, full), 1e-9) << Law::kName;
    }
  }
  EXPECT_GT(indefinite, 0) << Law::kName << ": no sample made the tangent indefinite";
}

// psd_method: diagonal_blocks where a law has it (isotropic laws, teran_muscle): PSD at the
// same large and inverted states; for an isotropic law it is the eigenvalue clamp itself.
TYPED_TEST(LawConformance, DiagonalBlocksProjectionHasNoNegativeEigenvalue) {
  using Law = TypeParam;
  if (!supportsPsdMethod<Law>(PsdMethod::kDiagonalBlocks))
    GTEST_SKIP() << Law::kName << " has no diagonal-blocks projection (refused in scenes)";
  std::mt19937 rng(16);
  LawOptions blocks, eigen;
  blocks.psdProjection = eigen.psdProjection = true;
  blocks.inversionThreshold = eigen.inversionThreshold = 0.05;
  blocks.psdMethod = PsdMethod::kDiagonalBlocks;
  for (int trial = 0; trial < 50; ++trial) {
    const auto p = this->params(rng);
    const Eigen::Matrix3d F = sampleGradient<Law>(rng, p, 0.6);
    LawPoint point = lawPoint(F, blocks);
    const Matrix9d projected = pointTangent<Law>(p, point, blocks);
    const Eigen::VectorXd lambda =
        Eigen::SelfAdjointEigenSolver<Matrix9d>(0.5 * (projected + projected.transpose()))
            .eigenvalues();
    EXPECT_GE(lambda.minCoeff(), -1e-10 * lambda.cwiseAbs().maxCoeff()) << Law::kName;
    if (Law::kIsotropic) {
      LawPoint other = lawPoint(F, eigen);
      EXPECT_LT(relative(projected, pointTangent<Law>(p, other, eigen)), 1e-12) << Law::kName;
    }
  }
}

TEST(RotationSvd, RotationsWithTheSignOnTheSmallestSingularValue) {
  std::mt19937 rng(16);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    Eigen::Matrix3d F;
    for (int i = 0; i < 9; ++i) F.data()[i] = n(rng);
    const RotationSvd s = rotationSvd(F);
    EXPECT_NEAR(s.U.determinant(), 1.0, 1e-12);
    EXPECT_NEAR(s.V.determinant(), 1.0, 1e-12);
    EXPECT_LT(relative(s.U * s.sigma.asDiagonal() * s.V.transpose(), F), 1e-12);
    EXPECT_GE(s.sigma(0), s.sigma(1));
    EXPECT_GE(s.sigma(1), std::abs(s.sigma(2)));
    EXPECT_EQ(s.sigma(2) < 0.0, F.determinant() < 0.0);
  }
}

// An inverted gradient gets the law's stress at F^ (finite) and that stress acts to undo the
// inversion: moving F against P raises det F.
TEST(InversionHandling, InvertedGradientsGetAFiniteRestoringStress) {
  std::mt19937 rng(17);
  const NeoHookeanLaw::Parameters p = sampleConstants<NeoHookeanLaw>();
  LawOptions options;
  options.inversionThreshold = 0.1;
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Matrix3d F = randomGradient(rng, 0.2);
    F.col(2) *= -0.5;  // reflected: det F < 0
    ASSERT_LT(F.determinant(), 0.0);
    EXPECT_FALSE(NeoHookeanLaw::stress(p, F).allFinite());  // the bare law is undefined there
    const LawPoint point = lawPoint(F, options);
    EXPECT_TRUE(point.clamped);
    EXPECT_GT(point.F.determinant(), 0.0);
    const Eigen::Matrix3d P = NeoHookeanLaw::stress(p, point.F);
    ASSERT_TRUE(P.allFinite());
    const Eigen::Matrix3d cofactor = VolumeLaw::cofactor(F);  // d det F / dF
    EXPECT_LT((cofactor.array() * P.array()).sum(), 0.0)
        << "the force -P must increase det F (trial " << trial << ")";
  }
  // Above the threshold nothing changes, bitwise.
  const Eigen::Matrix3d F = randomGradient(rng, 0.05);
  const LawPoint point = lawPoint(F, options);
  EXPECT_FALSE(point.clamped);
  EXPECT_EQ(point.F, F);
}

// The test that lets lawPoint skip the SVD never passes a gradient with a singular value below
// the threshold (random, stretched and nearly flat gradients, the threshold near their
// smallest singular value or below), and it does pass gradients near the identity.
TEST(InversionHandling, SvdIsSkippedOnlyWhereNoSingularValueIsBelowTheThreshold) {
  std::mt19937 rng(19);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> ratio(0.05, 1.1);
  int skipped = 0, kept = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    const double spread = trial % 3 == 0 ? 1.0 : trial % 3 == 1 ? 0.3 : 0.05;
    for (int i = 0; i < 9; ++i) F.data()[i] += spread * n(rng);
    if (trial % 5 == 0) F.col(trial % 3) *= 0.05;  // nearly flat
    const RotationSvd svd = rotationSvd(F);
    const double threshold = std::max(1e-3, std::abs(svd.sigma(2))) * ratio(rng);
    if (singularValuesSurelyAbove(F, threshold)) {
      ++skipped;
      EXPECT_GE(svd.sigma(2), threshold) << "trial " << trial;
      LawOptions options;
      options.inversionThreshold = threshold;
      const LawPoint point = lawPoint(F, options);
      EXPECT_FALSE(point.clamped);
      EXPECT_EQ(point.F, F);
    } else {
      ++kept;
    }
  }
  EXPECT_GT(skipped, 100);
  EXPECT_GT(kept, 100);
  for (int trial = 0; trial < 100; ++trial)
    EXPECT_TRUE(singularValuesSurelyAbove(randomGradient(rng, 0.1), 0.2));
}

// The volume law with r != 1 ("Adamss: Advanced Anisotropic Mass-Spring System", Eq. 2.101):
// the exact stress P = 2 p (J - r) cof F, i.e. S = 2 p J (J - r) C^-1. The printed Eq. 2.100
// has (2 E_kk - 1) where (2 E_kk + 1) belongs; here the stress is checked against the energy.
TEST(VolumeLaw, DrivenVolumeStressIsTheEnergyGradient) {
  std::mt19937 rng(18);
  const VolumeLaw::Parameters p{5e3, 0.8};
  EXPECT_FALSE(VolumeLaw::restStressFree(p));
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Matrix3d F = randomGradient(rng, 0.3);
    EXPECT_LT(relative(energyGradient<VolumeLaw>(p, F), VolumeLaw::stress(p, F)), 1e-6);
    // S = F^-1 P = 2 p J (J - r) C^-1 (the corrected 2.100 / 2.106).
    const double J = F.determinant();
    const Eigen::Matrix3d S = F.inverse() * VolumeLaw::stress(p, F);
    EXPECT_LT(relative(S, 2 * p.stiffness * J * (J - p.ratio) * (F.transpose() * F).inverse()),
              1e-12);
  }
}

}  // namespace
}  // namespace tt
