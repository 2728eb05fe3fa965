// The muscle law's two PSD projections and the diagonal-frame forms of M. Bao, "Derivation of
// Quasistatics and Landmark Optimization for Muscles", checked against code written here from
// the paper (with the corrections its errata list): Eq. 15 (P in the singular-value frame),
// the alpha/beta/eta summary of Sec. 4.5.1.4 (the isotropic 9 x 9 dP/dF in that frame), Eq. 45
// (the fibre differential), the projection of Sec. 5.6 (blocks clamped in that frame, the
// fibre tension derivative clamped at zero) and the finite-volume forces of Sec. 4.4.
//
// The reference here takes its own SVD (Eigen's JacobiSVD made into rotations), its own fibre
// curves (PhysBAM FACE_3D's, from their formulas), applies the 9 x 9 blocks to dF^ = U^T dF V
// instead of rotating a matrix, and uses no code of the law beyond its stress and tangent.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <random>

#include "../model_test_util.h"
#include "tissue_trainer/core/material/law_point.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "../random_draws.h"

namespace tt {
namespace {

constexpr double kThreshold = 0.25;  // PhysBAM's inversion threshold, the law's in scenes

// ---- the reference ------------------------------------------------------------------------

// Tension tau = d psi_f / d lam and tau' of the fibre (PhysBAM FACE_3D's C1 curves).
void referenceTension(const TeranMuscleLaw::Constants& k, double lam, double& tau, double& dtau) {
  const double e = lam - 1.0, a = std::fabs(e);
  double ta = 0.0, dta = 0.0;
  if (a < 0.4) {
    ta = 1.0 - 25.0 / 6.0 * e * e;
    dta = -25.0 / 3.0 * e;
  } else if (a < 0.6) {
    ta = 25.0 / 3.0 * (a - 0.6) * (a - 0.6);
    dta = (e > 0 ? 1.0 : -1.0) * 50.0 / 3.0 * (a - 0.6);
  }
  const double p1 = 0.05, p2 = 6.6;
  double tp = 0.0, dtp = 0.0;
  if (k.passiveFibre && lam > 1.4) {
    tp = p1 * p2 * (std::exp(0.4 * p2) - 1.0) * lam +
         p1 * (std::exp(0.4 * p2) * (1.0 - 1.4 * p2) + p2 - 1.0);
    dtp = p1 * p2 * (std::exp(0.4 * p2) - 1.0);
  } else if (k.passiveFibre && lam > 1.0) {
    tp = p1 * (std::exp(p2 * e) - p2 * e - 1.0);
    dtp = p1 * p2 * (std::exp(p2 * e) - 1.0);
  }
  tau = k.sigmaMax * (k.activation * ta + tp);
  dtau = k.sigmaMax * (k.activation * dta + dtp);
}

// F = U diag(sigma) V^T with U, V rotations and the sign of det F on sigma(2) (Irving et al.
// 2004), from Eigen's JacobiSVD.
struct Svd {
  Eigen::Matrix3d U, V;
  Eigen::Vector3d sigma;
};
Svd rotationOnlySvd(const Eigen::Matrix3d& F) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Svd s{svd.matrixU(), svd.matrixV(), svd.singularValues()};
  if (s.U.determinant() < 0) {
    s.U.col(2) *= -1.0;
    s.sigma(2) *= -1.0;
  }
  if (s.V.determinant() < 0) {
    s.V.col(2) *= -1.0;
    s.sigma(2) *= -1.0;
  }
  return s;
}

int vecIndex(int i, int j) { return i + 3 * j; }

// The isotropic dP/dF at diag(s), 9 x 9 on vec(dF^) (entry (i + 3 j, k + 3 l) = dP_ij/dF_kl),
// from the summary of Sec. 4.5.1.4 with the errata's two fixes (alpha: sigma_i^2 + sigma_j^2;
// eta13 = -(8B/3) Jcc^2 tr C + ...).
Matrix9d summaryTangent(const TeranMuscleLaw::Constants& k, const Eigen::Vector3d& s) {
  const double J = s.prod(), Jcc = std::pow(J, -2.0 / 3.0), lnJ = std::log(J);
  const double trC = s.squaredNorm(), trC2 = s.array().pow(4).sum();
  const double A = k.A, B = k.B, K = k.K;
  auto alpha = [&](int i, int j) {
    return 2.0 * Jcc * (A + B * Jcc * (trC - s(i) * s(i) - s(j) * s(j)));
  };
  auto beta = [&](int i, int j) {
    return (2.0 / 3.0 * Jcc * (A * trC + B * Jcc * (trC * trC - trC2)) - K * lnJ) /
               (s(i) * s(j)) -
           2.0 * B * Jcc * Jcc * s(i) * s(j);
  };
  Eigen::Matrix3d eta = Eigen::Matrix3d::Zero();
  eta(0, 0) = 4.0 * B * Jcc * Jcc;
  eta(0, 2) = eta(2, 0) = -Jcc / 3.0 * (4.0 * A + 8.0 * B * Jcc * trC);
  eta(1, 2) = eta(2, 1) = 8.0 * B / 3.0 * Jcc * Jcc;
  eta(2, 2) = Jcc / 9.0 * (4.0 * A * trC + 8.0 * B * Jcc * (trC * trC - trC2)) + K;
  Eigen::Matrix3d Fbase;
  for (int i = 0; i < 3; ++i) Fbase.row(i) << s(i), s(i) * s(i) * s(i), 1.0 / s(i);
  const Eigen::Matrix3d gamma = Fbase * eta * Fbase.transpose();
  Matrix9d M = Matrix9d::Zero();
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      M(vecIndex(a, a), vecIndex(b, b)) = gamma(a, b) + (a == b ? alpha(a, a) + beta(a, a) : 0.0);
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j) {  // B_ij on (F_ij, F_ji)
      const int ij = vecIndex(i, j), ji = vecIndex(j, i);
      M(ij, ij) = M(ji, ji) = alpha(i, j);
      M(ij, ji) = M(ji, ij) = beta(i, j);
    }
  return M;
}

// The paper's projection of the summary's blocks: the 3 x 3 block by its eigenvalues, each
// 2 x 2 block [[a, b], [b, a]] by its eigenvalues a + b and a - b (eigenvectors (1, +-1)).
Matrix9d clampSummaryBlocks(const Matrix9d& M) {
  Matrix9d out = Matrix9d::Zero();
  Eigen::Matrix3d D;
  const int diag[3] = {0, 4, 8};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) D(a, b) = M(diag[a], diag[b]);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(D);
  D = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
      eig.eigenvectors().transpose();
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) out(diag[a], diag[b]) = D(a, b);
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j) {
      const int ij = vecIndex(i, j), ji = vecIndex(j, i);
      const double plus = std::max(M(ij, ij) + M(ij, ji), 0.0);
      const double minus = std::max(M(ij, ij) - M(ij, ji), 0.0);
      out(ij, ij) = out(ji, ji) = 0.5 * (plus + minus);
      out(ij, ji) = out(ji, ij) = 0.5 * (plus - minus);
    }
  return out;
}

// M : dF^ for a 9 x 9 M on vec.
Eigen::Matrix3d apply(const Matrix9d& M, const Eigen::Matrix3d& dF) {
  Eigen::Matrix3d out;
  Eigen::Map<Eigen::Matrix<double, 9, 1>>(out.data()) =
      M * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dF.data());
  return out;
}

// Eq. 45 in the diagonal frame (lam = |F^ f_m|, f_m = V^T a0, T = tau, T' = tau' or its clamp).
Eigen::Matrix3d eq45(const TeranMuscleLaw::Constants& k, const Eigen::Vector3d& s,
                     const Eigen::Vector3d& fm, const Eigen::Matrix3d& dFhat, bool clampTprime) {
  const Eigen::Vector3d b = s.asDiagonal() * fm;
  const double lam = b.norm();
  double T, dT;
  referenceTension(k, lam, T, dT);
  if (clampTprime) dT = std::max(dT, 0.0);
  const double c1 = T / lam, c2 = (dT - c1) / (lam * lam);
  const Eigen::Vector3d u = dFhat * fm;
  return (c1 * u + c2 * u.dot(b) * b) * fm.transpose();
}

// The paper's projected dP (Sec. 5.6) of the non-deviatoric model at F for dF, with the
// singular values clamped at `threshold` (Sec. 5.5).
Eigen::Matrix3d referenceProjectedDifferential(const TeranMuscleLaw::Parameters& p,
                                               const Eigen::Matrix3d& F, const Eigen::Matrix3d& dF,
                                               double threshold) {
  const Svd svd = rotationOnlySvd(F);
  const Eigen::Vector3d s = svd.sigma.cwiseMax(threshold);
  const Eigen::Matrix3d dFhat = svd.U.transpose() * dF * svd.V;
  const Eigen::Matrix3d dPhat = apply(clampSummaryBlocks(summaryTangent(p.k, s)), dFhat) +
                                eq45(p.k, s, svd.V.transpose() * p.a0, dFhat, true);
  return svd.U * dPhat * svd.V.transpose();
}

// P at F = U diag(s) V^T by Eq. 15 (deviatoric lam, T = tau / lam as Sec. 4.3.3 defines it,
// C = F^2 non-deviatoric) or, for lam = |F a0|, by Eq. 15's isotropic part with p_f lacking the
// T lam^2 term plus (tau / lam) F^ f_m f_m^T (the model Eq. 45 differentiates).
Eigen::Matrix3d eq15Stress(const TeranMuscleLaw::Parameters& p, const Eigen::Matrix3d& F) {
  const Svd svd = rotationOnlySvd(F);
  const Eigen::Vector3d s = svd.sigma, fm = svd.V.transpose() * p.a0;
  const Eigen::Matrix3d Fh = s.asDiagonal();
  const double J = s.prod(), Jcc = std::pow(J, -2.0 / 3.0);
  const double trC = s.squaredNorm(), trC2 = s.array().pow(4).sum();
  const double w1 = 2.0 * Jcc * p.k.A, w2 = 2.0 * Jcc * Jcc * p.k.B, w12 = w1 + trC * w2;
  const double pressure = p.k.K * std::log(J);
  const Eigen::Matrix3d Finv = s.cwiseInverse().asDiagonal();
  Eigen::Matrix3d Phat = w12 * Fh - w2 * Fh * Fh * Fh;
  double tau, dtau;
  if (p.k.deviatoricStretch) {
    const double lam = std::cbrt(1.0 / J) * (Fh * fm).norm();
    referenceTension(p.k, lam, tau, dtau);
    const double T = tau / lam;
    const double pf = (w12 * trC - w2 * trC2 + T * lam * lam) / 3.0;
    Phat += (pressure - pf) * Finv + Jcc * T * Fh * fm * fm.transpose();
  } else {
    const double lam = (Fh * fm).norm();
    referenceTension(p.k, lam, tau, dtau);
    const double pf = (w12 * trC - w2 * trC2) / 3.0;
    Phat += (pressure - pf) * Finv + tau / lam * Fh * fm * fm.transpose();
  }
  return svd.U * Phat * svd.V.transpose();
}

// ---- helpers ------------------------------------------------------------------------------

TeranMuscleLaw::Parameters sampleMuscle(std::mt19937& rng, double activation, bool deviatoric) {
  TeranMuscleLaw::Constants k;  // PhysBAM's defaults
  k.activation = activation;
  k.deviatoricStretch = deviatoric;
  return TeranMuscleLaw::parameters(k, testutil::frameFrom(testutil::randomUnit(rng)));
}

Eigen::Matrix3d psdRandomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix3d X;
  for (int i = 0; i < 9; ++i) X.data()[i] = n(rng);
  Eigen::HouseholderQR<Eigen::Matrix3d> qr(X);
  Eigen::Matrix3d Q = qr.householderQ();
  if (Q.determinant() < 0) Q.col(0) *= -1.0;
  return Q;
}

// Q diag(s) R with s uniform in [lo, hi] (a negative lo reaches inverted gradients).
Eigen::Matrix3d gradientWithSingularValues(std::mt19937& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  const Eigen::Vector3d s = testutil::drawVector(u, rng);
  const Eigen::Matrix3d right = psdRandomRotation(rng);  // the right one first, as g++ did
  return psdRandomRotation(rng) * s.asDiagonal() * right;
}

Eigen::Matrix3d randomDirection(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix3d d;
  for (int i = 0; i < 9; ++i) d.data()[i] = n(rng);
  return d;
}

double psdRelative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(b.lpNorm<Eigen::Infinity>(), 1e-300);
}

LawOptions diagonalBlocks(double threshold) {
  LawOptions o;
  o.inversionThreshold = threshold;
  o.psdProjection = true;
  o.psdMethod = PsdMethod::kDiagonalBlocks;
  return o;
}

Matrix9d projectedTangent(const TeranMuscleLaw::Parameters& p, const Eigen::Matrix3d& F,
                          const LawOptions& options) {
  LawPoint point = lawPoint(F, options);
  return pointTangent<TeranMuscleLaw>(p, point, options);
}

double smallestRelativeEigenvalue(const Matrix9d& A) {
  const Eigen::VectorXd l = Eigen::SelfAdjointEigenSolver<Matrix9d>(0.5 * (A + A.transpose()))
                                .eigenvalues();
  return l.minCoeff() / l.cwiseAbs().maxCoeff();
}

// ---- (d) the diagonal-frame forms equal the law's direct derivatives -----------------------

TEST(TeranMusclePaperForms, Eq15StressIsTheLawsStress) {
  std::mt19937 rng(101);
  double worst[2] = {0, 0};
  for (int trial = 0; trial < 200; ++trial)
    for (int deviatoric = 0; deviatoric < 2; ++deviatoric) {
      const auto p = sampleMuscle(rng, trial % 3 == 0 ? 0.0 : 0.7, deviatoric);
      const Eigen::Matrix3d F = gradientWithSingularValues(rng, 0.6, 1.6);
      const double e = psdRelative(eq15Stress(p, F), TeranMuscleLaw::stress(p, F));
      worst[deviatoric] = std::max(worst[deviatoric], e);
      EXPECT_LT(e, 1e-11) << "deviatoric " << deviatoric;
    }
  std::printf("Eq. 15 vs the law's P, worst relative difference: non-deviatoric %.2g, "
              "deviatoric %.2g\n", worst[0], worst[1]);
}

TEST(TeranMusclePaperForms, SummaryBlocksAreTheLawsIsotropicTangent) {
  std::mt19937 rng(102);
  double worst = 0.0, worstOffBlock = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    TeranMuscleLaw::Parameters p = sampleMuscle(rng, 0.0, true);
    p.k.sigmaMax = 0.0;  // the isotropic part alone
    std::uniform_real_distribution<double> u(0.3, 2.0);
    const Eigen::Vector3d s = testutil::drawVector(u, rng);
    const Matrix9d law = TeranMuscleLaw::tangent(p, Eigen::Matrix3d(s.asDiagonal()));
    const Matrix9d summary = summaryTangent(p.k, s);
    worst = std::max(worst, psdRelative(summary, law));
    EXPECT_LT(psdRelative(summary, law), 1e-11) << s.transpose();
    // Off the blocks the law's tangent is zero (to round-off): the block form loses nothing.
    Matrix9d offBlock = law;
    for (int r = 0; r < 9; ++r)
      for (int c = 0; c < 9; ++c)
        if (summary(r, c) != 0.0 || r == c) offBlock(r, c) = 0.0;
    worstOffBlock = std::max(worstOffBlock, offBlock.cwiseAbs().maxCoeff() /
                                                law.cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worstOffBlock, 1e-12);
  std::printf("alpha/beta/eta summary vs the law's isotropic tangent: worst %.2g; off-block "
              "entries of the law's tangent up to %.2g of its largest\n", worst, worstOffBlock);
}

// The general-F stiffness: dP = U [M : (U^T dF V)] V^T + U (Eq. 45) V^T with f_m = V^T a0.
TEST(TeranMusclePaperForms, SvdFrameStiffnessIsTheLawsDifferential) {
  std::mt19937 rng(103);
  double worst = 0.0;
  for (int trial = 0; trial < 300; ++trial) {
    const auto p = sampleMuscle(rng, trial % 2 ? 0.8 : 0.0, false);
    const Eigen::Matrix3d F = gradientWithSingularValues(rng, 0.5, 1.8);
    const Eigen::Matrix3d dF = randomDirection(rng);
    const Svd svd = rotationOnlySvd(F);
    const Eigen::Matrix3d dFhat = svd.U.transpose() * dF * svd.V;
    const Eigen::Matrix3d dP =
        svd.U *
        (apply(summaryTangent(p.k, svd.sigma), dFhat) +
         eq45(p.k, svd.sigma, svd.V.transpose() * p.a0, dFhat, false)) *
        svd.V.transpose();
    const double e = psdRelative(dP, TeranMuscleLaw::stressDifferential(p, F, dF));
    worst = std::max(worst, e);
    EXPECT_LT(e, 1e-10);
  }
  std::printf("SVD-frame stiffness (summary + Eq. 45) vs the law's dP: worst %.2g\n", worst);
}

// ---- (a) the law's diagonal_blocks projection equals the reference -------------------------

TEST(TeranMusclePsd, DiagonalBlocksEqualsThePapersProjectionAtPoints) {
  std::mt19937 rng(104);
  int inverted = 0, clampedT = 0;
  double worst = 0.0;
  for (int trial = 0; trial < 300; ++trial) {
    const auto p = sampleMuscle(rng, trial % 3 == 0 ? 0.0 : 0.9, false);
    const Eigen::Matrix3d F = gradientWithSingularValues(rng, trial % 2 ? -0.6 : 0.4, 1.7);
    inverted += F.determinant() < 0;
    double tau, dtau;
    referenceTension(p.k, (F * p.a0).norm(), tau, dtau);
    clampedT += dtau < 0;
    const LawOptions options = diagonalBlocks(kThreshold);
    const Matrix9d A = projectedTangent(p, F, options);
    for (int d = 0; d < 3; ++d) {
      const Eigen::Matrix3d dF = randomDirection(rng);
      const Eigen::Matrix3d ref = referenceProjectedDifferential(p, F, dF, kThreshold);
      const double e = psdRelative(apply(A, dF), ref);
      worst = std::max(worst, e);
      EXPECT_LT(e, 1e-8) << "det F " << F.determinant();
    }
  }
  EXPECT_GT(inverted, 50);
  EXPECT_GT(clampedT, 20);  // the fibre clamp is exercised
  std::printf("diagonal_blocks vs the paper's projection (300 gradients, %d inverted, %d with "
              "tau' < 0): worst %.2g\n", inverted, clampedT, worst);
}

// The same through the element model: -df/dx d of random tets, with and without inversion.
TEST(TeranMusclePsd, DiagonalBlocksElementProductsEqualThePapersProjection) {
  std::mt19937 rng(105);
  double worst = 0.0;
  int inverted = 0;
  for (int trial = 0; trial < 100; ++trial) {
    Mesh mesh = testutil::randomTet(rng);
    const auto p = TeranMuscleLaw::parameters(sampleMuscle(rng, 0.9, false).k,
                                              mesh.fibreFrame[0]);
    const HyperelasticModel<TeranMuscleLaw> model(mesh, {p.k}, diagonalBlocks(kThreshold));
    Eigen::VectorXd x = testutil::perturbed(mesh, 0.004, rng);
    if (trial % 2) {  // push node 0 through the opposite face: an inverted tet
      const Eigen::Vector3d centroid =
          (x.segment<3>(3) + x.segment<3>(6) + x.segment<3>(9)) / 3.0;
      x.segment<3>(0) += 1.5 * (centroid - x.segment<3>(0));
    }
    const Eigen::VectorXd d = testutil::perturbed(mesh, 1.0, rng) - testutil::restVector(mesh);
    Eigen::VectorXd product = Eigen::VectorXd::Zero(12);
    model.addStiffnessTimes(x, d, 1.0, product);  // += (df/dx) d
    // Reference: F = Ds Dm^-1, delta f_p = -V0 dP g_p, g_1 = -(g_2 + g_3 + g_4).
    Eigen::Matrix3d Dm, Ds, dDs;
    for (int c = 0; c < 3; ++c) {
      Dm.col(c) = mesh.rest.col(c + 1) - mesh.rest.col(0);
      Ds.col(c) = x.segment<3>(3 * (c + 1)) - x.segment<3>(0);
      dDs.col(c) = d.segment<3>(3 * (c + 1)) - d.segment<3>(0);
    }
    const Eigen::Matrix3d DmInv = Dm.inverse(), F = Ds * DmInv;
    inverted += F.determinant() < 0;
    const Eigen::Matrix3d dP = referenceProjectedDifferential(p, F, dDs * DmInv, kThreshold);
    const double V0 = std::fabs(Dm.determinant()) / 6.0;
    Eigen::VectorXd ref(12);
    for (int q = 1; q < 4; ++q) ref.segment<3>(3 * q) = -V0 * dP * DmInv.row(q - 1).transpose();
    ref.segment<3>(0) = -(ref.segment<3>(3) + ref.segment<3>(6) + ref.segment<3>(9));
    const double e = testutil::relDiff(product, ref);
    worst = std::max(worst, e);
    EXPECT_LT(e, 1e-8) << "det F " << F.determinant();
  }
  EXPECT_GT(inverted, 30);
  std::printf("diagonal_blocks element products vs the paper's projection (100 tets, %d "
              "inverted): worst %.2g\n", inverted, worst);
}

// ---- (b) PSD, (c) the tangent itself where it already is PSD -------------------------------

TEST(TeranMusclePsd, DiagonalBlocksTangentIsPositiveSemiDefinite) {
  std::mt19937 rng(106);
  int indefinite = 0;
  double worst = 1.0;
  for (int trial = 0; trial < 400; ++trial) {
    const bool deviatoric = trial % 2;
    const auto p = sampleMuscle(rng, trial % 4 < 2 ? 0.9 : 0.0, deviatoric);
    const Eigen::Matrix3d F = gradientWithSingularValues(rng, -0.8, 2.2);
    const LawOptions options = diagonalBlocks(kThreshold);
    LawPoint point = lawPoint(F, options);
    indefinite += smallestRelativeEigenvalue(lawTangent<TeranMuscleLaw>(p, point.F)) < 0.0;
    const double l = smallestRelativeEigenvalue(projectedTangent(p, F, options));
    worst = std::min(worst, l);
    EXPECT_GE(l, -1e-10) << "deviatoric " << deviatoric << " det F " << F.determinant();
  }
  EXPECT_GT(indefinite, 100);
  std::printf("diagonal_blocks: %d of 400 tangents indefinite before; smallest eigenvalue "
              "after / largest |eigenvalue| %.2g\n", indefinite, worst);
}

// diagonal_blocks projects the isotropic part and the fibre part separately, so it leaves the
// tangent unchanged where both parts are PSD (the whole tangent then is). States stretched a
// little in every direction, the passive fibre; the count of states whose whole tangent is PSD
// but one part is not (there the method does change it) is printed.
TEST(TeranMusclePsd, DiagonalBlocksLeavesAPsdTangentUnchanged) {
  std::mt19937 rng(107);
  int compared = 0, partIndefinite = 0;
  double worst = 0.0;
  for (int trial = 0; trial < 300; ++trial) {
    const bool deviatoric = trial % 2;
    const auto p = sampleMuscle(rng, 0.0, deviatoric);
    const Eigen::Matrix3d F = gradientWithSingularValues(rng, 1.0, 1.15);
    TeranMuscleLaw::Parameters isotropic = p, fibre = p;
    isotropic.k.sigmaMax = 0.0;
    fibre.k.A = fibre.k.B = fibre.k.K = 0.0;
    const Matrix9d A = lawTangent<TeranMuscleLaw>(p, F);
    if (smallestRelativeEigenvalue(A) < 0.0) continue;
    const Matrix9d Afibre = lawTangent<TeranMuscleLaw>(fibre, F);
    const bool fibreIsZero = Afibre.cwiseAbs().maxCoeff() == 0.0;
    if (smallestRelativeEigenvalue(lawTangent<TeranMuscleLaw>(isotropic, F)) < -1e-14 ||
        (!fibreIsZero && smallestRelativeEigenvalue(Afibre) < -1e-14)) {
      ++partIndefinite;
      continue;
    }
    ++compared;
    const Matrix9d projected = projectedTangent(p, F, diagonalBlocks(kThreshold));
    const double e = psdRelative(projected, 0.5 * (A + A.transpose()));
    worst = std::max(worst, e);
    EXPECT_LT(e, 1e-10) << "deviatoric " << deviatoric;
  }
  EXPECT_GT(compared, 100);
  std::printf("diagonal_blocks equals a PSD tangent with PSD parts: %d of 300 small stretches "
              "compared, worst %.2g; %d had a PSD tangent with an indefinite part\n",
              compared, worst, partIndefinite);
}

// The two methods differ only where the tangent is indefinite; report by how much on
// inverted gradients (the docs quote this line).
TEST(TeranMusclePsd, MethodsDifferOnlyWhereTheTangentIsIndefinite) {
  std::mt19937 rng(108);
  LawOptions eigen = diagonalBlocks(kThreshold);
  eigen.psdMethod = PsdMethod::kEigen;
  double sum = 0.0, largest = 0.0;
  int n = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const auto p = sampleMuscle(rng, 0.9, false);
    std::uniform_real_distribution<double> u(0.3, 1.5), w(-0.8, -0.05);
    const double z = w(rng), y = u(rng), x = u(rng);  // det F < 0; g++'s order
    const Eigen::Vector3d s(x, y, z);
    const Eigen::Matrix3d right = psdRandomRotation(rng);
    const Eigen::Matrix3d F = psdRandomRotation(rng) * s.asDiagonal() * right;
    const Matrix9d a = projectedTangent(p, F, diagonalBlocks(kThreshold));
    const Matrix9d b = projectedTangent(p, F, eigen);
    const double e = (a - b).norm() / b.norm();
    sum += e;
    largest = std::max(largest, e);
    ++n;
  }
  ASSERT_EQ(n, 200);
  EXPECT_GT(largest, 1e-6);  // they are different projections of an indefinite tangent
  std::printf("inverted gradients (%d, activation 0.9, non-deviatoric): |A_blocks - A_eigen|_F "
              "/ |A_eigen|_F mean %.3g, largest %.3g\n", n, sum / n, largest);
}

// ---- (e) the finite-volume forces of Sec. 4.4 ---------------------------------------------

TEST(TeranMusclePaperForms, FiniteVolumeForcesAreTheElementForces) {
  std::mt19937 rng(109);
  double worst = 0.0, worstBm = 0.0;
  int compared = 0;
  for (int trial = 0; trial < 100; ++trial) {
    Mesh mesh = testutil::randomTet(rng);
    const auto p = TeranMuscleLaw::parameters(sampleMuscle(rng, 0.5, trial % 2).k,
                                              mesh.fibreFrame[0]);
    const HyperelasticModel<TeranMuscleLaw> model(mesh, {p.k}, LawOptions{});
    const Eigen::VectorXd x = testutil::perturbed(mesh, 0.002, rng);
    const Eigen::VectorXd f = testutil::force(model, x);
    Eigen::Matrix3d Dm, Ds;
    for (int c = 0; c < 3; ++c) {
      Dm.col(c) = mesh.rest.col(c + 1) - mesh.rest.col(0);
      Ds.col(c) = x.segment<3>(3 * (c + 1)) - x.segment<3>(0);
    }
    const Eigen::Matrix3d F = Ds * Dm.inverse();
    if (!(F.determinant() > 0.0)) continue;  // the law (no inversion handling) needs J > 0
    ++compared;
    const Eigen::Matrix3d P = TeranMuscleLaw::stress(p, F);
    // Outward area-weighted normals of the rest faces; face k is opposite node k.
    Eigen::Matrix<double, 3, 4> AN;
    const Eigen::Vector3d centroid = mesh.rest.rowwise().mean();
    for (int k = 0; k < 4; ++k) {
      const int a = (k + 1) % 4, b = (k + 2) % 4, c = (k + 3) % 4;
      Eigen::Vector3d n =
          0.5 * (mesh.rest.col(b) - mesh.rest.col(a)).cross(mesh.rest.col(c) - mesh.rest.col(a));
      if (n.dot(mesh.rest.col(a) - centroid) < 0) n = -n;
      AN.col(k) = n;
    }
    Eigen::VectorXd fvm(12);
    Eigen::Matrix3d Bm;
    for (int i = 0; i < 4; ++i) {
      Eigen::Vector3d incident = Eigen::Vector3d::Zero();  // the faces touching node i
      for (int k = 0; k < 4; ++k)
        if (k != i) incident += AN.col(k);
      const Eigen::Vector3d b = -incident / 3.0;
      fvm.segment<3>(3 * i) = P * b;
      if (i > 0) Bm.col(i - 1) = b;
    }
    const double V = std::fabs(Dm.determinant()) / 6.0;
    worstBm = std::max(worstBm, psdRelative(Bm, -V * Dm.inverse().transpose()));
    const double e = testutil::relDiff(fvm, f);
    worst = std::max(worst, e);
    EXPECT_LT(e, 1e-11);
  }
  EXPECT_LT(worstBm, 1e-12);
  EXPECT_GT(compared, 90);
  std::printf("Sec. 4.4 forces vs the element forces (%d tets): worst %.2g; B_m vs -V Dm^-T: "
              "worst %.2g\n", compared, worst, worstBm);
}

}  // namespace
}  // namespace tt
