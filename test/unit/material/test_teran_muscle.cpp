// The muscle law teran_muscle (M. Bao, "Derivation of Quasistatics and Landmark Optimization
// for Muscles", Sec. 4.3, Eq. 10). The finite-difference, frame-indifference and projection
// checks in every option combination are in the conformance suite (test_law_conformance.cpp);
// here: the fibre curves against reference values, the two fibre stretches, the energy
// constant at rest, forces linear in the activation (Sec. 1, Eq. 4), inverted elements and
// the projected element stiffness.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <random>

#include "../model_test_util.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/model/muscle_activation.h"

namespace tt {
namespace {

using testutil::force;
using testutil::perturbed;
using testutil::randomTet;
using testutil::restVector;

// t_a, t_p, Phi_a, Phi_p at lam: the curves and their integrals from 1 by composite Simpson
// quadrature split at the break points, computed independently of this code.
struct CurveReference {
  double lam, ta, tp, phiA, phiP;
};
const CurveReference kCurves[] = {
    {0.30, 0, 0, -0.333333333333, 0},
    {0.50, 0.0833333333333, 0, -0.330555555556, 0},
    {0.70, 0.625, 0, -0.2625, 0},
    {0.90, 0.958333333333, 0, -0.0986111111111, 0},
    {1.00, 1, 0, 0, 0},
    {1.10, 0.958333333333, 0.0137396167201, 0.0986111111111, 0.000431760109106},
    {1.30, 0.625, 0.213137149258, 0.2625, 0.0174435074633},
    {1.50, 0.0833333333333, 0.948095899442, 0.330555555556, 0.125522679808},
    {2.00, 0, 3.09527449472, 0.333333333333, 1.13636527835},
};

TEST(TeranMuscle, FibreCurvesMatchTheReferenceValues) {
  std::printf("lam    t_a ref      t_a          t_p ref      t_p          Phi_a        Phi_p\n");
  for (const CurveReference& r : kCurves) {
    double pa, ta, da, pp, tp, dp;
    MuscleFibreCurves::active(r.lam, pa, ta, da);
    MuscleFibreCurves::passive(r.lam, pp, tp, dp);
    std::printf("%.2f   %-11.6g  %-11.6g  %-11.6g  %-11.6g  %-11.6g  %-11.6g\n", r.lam, r.ta, ta,
                r.tp, tp, pa, pp);
    EXPECT_NEAR(ta, r.ta, 1e-11) << r.lam;
    EXPECT_NEAR(tp, r.tp, 1e-11) << r.lam;
    EXPECT_NEAR(pa, r.phiA, 1e-11) << r.lam;
    EXPECT_NEAR(pp, r.phiP, 1e-11) << r.lam;
  }
}

// Phi' = t and t' = dt everywhere, and t continuous with its derivative (C1) at the breaks.
TEST(TeranMuscle, FibreCurvesAreC1WithConsistentDerivatives) {
  using Curve = void (*)(double, double&, double&, double&);
  for (Curve curve : {Curve(&MuscleFibreCurves::active), Curve(&MuscleFibreCurves::passive)}) {
    for (double lam = 0.2; lam < 2.5; lam += 0.0137) {
      const double h = 1e-6;
      double p0, t0, d0, pp, tp, dp, pm, tm, dm;
      curve(lam, p0, t0, d0);
      curve(lam + h, pp, tp, dp);
      curve(lam - h, pm, tm, dm);
      EXPECT_NEAR((pp - pm) / (2 * h), t0, 1e-7) << lam;
      EXPECT_NEAR((tp - tm) / (2 * h), d0, 1e-5) << lam;
    }
    for (double lam : {0.4, 0.6, 1.0, 1.4, 1.6}) {
      double pa, ta, da, pb, tb, db;
      curve(lam - 1e-12, pa, ta, da);
      curve(lam + 1e-12, pb, tb, db);
      EXPECT_NEAR(ta, tb, 1e-9) << lam;
      EXPECT_NEAR(da, db, 1e-9) << lam;
    }
  }
}

TeranMuscleLaw::Parameters muscle(double alpha, bool deviatoric) {
  TeranMuscleLaw::Constants k;
  k.activation = alpha;
  k.deviatoricStretch = deviatoric;
  return TeranMuscleLaw::parameters(k, testutil::frameFrom(Eigen::Vector3d(1, 2, 2) / 3.0));
}

// The two fibre stretches: a pure dilation s I leaves the deviatoric stretch at 1 (no fibre
// energy) and makes the non-deviatoric one s; an isochoric stretch along the fibre gives both
// the same lam.
TEST(TeranMuscle, FibreStretchOptions) {
  const double s = 1.2;
  const Eigen::Matrix3d dilation = s * Eigen::Matrix3d::Identity();
  const auto dev = muscle(0.7, true), nondev = muscle(0.7, false);
  const auto passiveShell = muscle(0.0, true);  // the isotropic part plus zero fibre energy at lam 1
  double psi, tau, dtau;
  TeranMuscleLaw::fibre(nondev.k, s, psi, tau, dtau);
  EXPECT_NEAR(TeranMuscleLaw::energy(dev, dilation), TeranMuscleLaw::energy(passiveShell, dilation),
              1e-12 * TeranMuscleLaw::energy(dev, dilation));
  EXPECT_NEAR(TeranMuscleLaw::energy(nondev, dilation) - TeranMuscleLaw::energy(dev, dilation), psi,
              1e-9 * std::abs(psi));
  // Isochoric: lam along a0, 1/sqrt(lam) across.
  const Eigen::Vector3d a0 = dev.a0;
  const double lam = 1.25;
  const Eigen::Matrix3d F = (1.0 / std::sqrt(lam)) * Eigen::Matrix3d::Identity() +
                            (lam - 1.0 / std::sqrt(lam)) * a0 * a0.transpose();
  EXPECT_NEAR(F.determinant(), 1.0, 1e-14);
  EXPECT_NEAR(TeranMuscleLaw::energy(dev, F), TeranMuscleLaw::energy(nondev, F),
              1e-12 * TeranMuscleLaw::energy(dev, F));
  // At J = 1 the deviatoric d lam / dF carries the extra -(lam/3) F^-T.
  TeranMuscleLaw::fibre(dev.k, lam, psi, tau, dtau);
  const Eigen::Matrix3d expected = -tau * lam / 3.0 * F.inverse().transpose();
  EXPECT_LT((TeranMuscleLaw::stress(dev, F) - TeranMuscleLaw::stress(nondev, F) - expected).norm(),
            1e-9 * expected.norm());
}

// Eq. 10 as written: psi(I) = 3 (A + B), so an element at rest has energy V0 3 (A + B).
// The law's own tangent (one State for the nine differentials) is bitwise the nine
// stressDifferential columns, for both fibre-stretch forms, active and passive.
TEST(TeranMuscle, OwnTangentIsTheNineDifferentials) {
  std::mt19937 rng(70);
  std::normal_distribution<double> n(0.0, 0.2);
  for (int trial = 0; trial < 40; ++trial) {
    TeranMuscleLaw::Constants k;
    k.deviatoricStretch = trial % 2 == 0;
    k.activation = trial % 3 == 0 ? 0.0 : 0.7;
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity(), frame;
    for (int i = 0; i < 9; ++i) F.data()[i] += n(rng);
    frame = Eigen::Matrix3d::Identity() + 0.3 * Eigen::Matrix3d::Random();
    const TeranMuscleLaw::Parameters p = TeranMuscleLaw::parameters(k, frame);
    const Matrix9d A = TeranMuscleLaw::tangent(p, F);
    for (int c = 0; c < 9; ++c) {
      Eigen::Matrix3d dF = Eigen::Matrix3d::Zero();
      dF(c % 3, c / 3) = 1.0;
      const Eigen::Matrix3d dP = TeranMuscleLaw::stressDifferential(p, F, dF);
      if (F.determinant() > 0.0) {
        using Vector9d = Eigen::Matrix<double, 9, 1>;
        const Vector9d column = A.col(c);
        EXPECT_TRUE(column == Eigen::Map<const Vector9d>(dP.data())) << trial << ", " << c;
      } else {
        EXPECT_FALSE(A.allFinite());
      }
    }
    EXPECT_EQ(lawTangent<TeranMuscleLaw>(p, F).allFinite(), A.allFinite());
  }
}

TEST(TeranMuscle, EnergyAtRestIsTheConstant) {
  std::mt19937 rng(71);
  const Mesh mesh = randomTet(rng);
  TeranMuscleLaw::Constants k;
  k.A = 5e3;
  k.B = 1e3;
  const HyperelasticModel<TeranMuscleLaw> model(mesh, {k}, {});
  const double V0 = tetVolume(mesh.rest, mesh.tets[0]);
  EXPECT_NEAR(model.energy(restVector(mesh)), V0 * 3.0 * (k.A + k.B), 1e-14 * V0 * 3e4);
  EXPECT_LT(force(model, restVector(mesh)).norm(), 1e-9);  // alpha = 0: no force at rest
}

// Sec. 1, Eq. 4: f(alpha) = f0 + alpha f1, exactly (the law is linear in alpha).
TEST(TeranMuscle, ForcesAreLinearInTheActivation) {
  std::mt19937 rng(72);
  const Mesh mesh = testutil::boxMesh(2, 2, 2, 0.01, rng);
  for (bool deviatoric : {true, false}) {
    auto model = [&](double alpha) {
      TeranMuscleLaw::Constants k;
      k.activation = alpha;
      k.deviatoricStretch = deviatoric;
      return HyperelasticModel<TeranMuscleLaw>(mesh, {k, k}, {0.25, false});  // two material ids
    };
    const Eigen::VectorXd x = perturbed(mesh, 0.15 * 0.01, rng);
    const Eigen::VectorXd f0 = force(model(0.0), x), f1 = force(model(1.0), x) - f0;
    ASSERT_GT(f1.norm(), 1e-3 * f0.norm());
    for (double alpha : {0.25, 0.6, 0.9}) {
      const Eigen::VectorXd f = force(model(alpha), x);
      EXPECT_LT((f - f0 - alpha * f1).lpNorm<Eigen::Infinity>(),
                1e-10 * f.lpNorm<Eigen::Infinity>())
          << alpha;
    }
  }
}

// A tet pushed through its opposite face: with the threshold the forces are finite and undo
// the inversion (the force along -P raises det F); the stiffness is the Hessian at F_c.
TEST(TeranMuscle, InvertedElementsGetFiniteRestoringForces) {
  std::mt19937 rng(73);
  for (int trial = 0; trial < 40; ++trial) {
    const Mesh mesh = randomTet(rng);
    Eigen::VectorXd x = perturbed(mesh, 0.05 * 0.01, rng);
    // Node 0 mirrored through the plane of the other three.
    const Eigen::Vector3d p1 = x.segment<3>(3), p2 = x.segment<3>(6), p3 = x.segment<3>(9);
    const Eigen::Vector3d n = (p2 - p1).cross(p3 - p1).normalized();
    const Eigen::Vector3d p0 = x.segment<3>(0);
    x.segment<3>(0) = p0 - 2.5 * n.dot(p0 - p1) * n;
    ASSERT_LT(tetVolume(Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, 4), mesh.tets[0]), 0.0);
    TeranMuscleLaw::Constants k;
    k.activation = 0.5;
    k.deviatoricStretch = trial % 2 == 0;
    const HyperelasticModel<TeranMuscleLaw> bare(mesh, {k}, {});
    EXPECT_FALSE(force(bare, x).allFinite());
    for (bool psd : {false, true}) {
      const HyperelasticModel<TeranMuscleLaw> model(mesh, {k}, {0.25, psd});
      const Eigen::VectorXd f = force(model, x);
      ASSERT_TRUE(f.allFinite());
      EXPECT_TRUE(std::isfinite(model.energy(x)));
      EXPECT_TRUE(testutil::denseStiffness(model, mesh, x).allFinite());
      // A small step along f raises the signed volume.
      const double h = 1e-3 * 0.01 / f.lpNorm<Eigen::Infinity>();
      const Eigen::VectorXd y = x + h * f;
      EXPECT_GT(tetVolume(Eigen::Map<const Eigen::Matrix3Xd>(y.data(), 3, 4), mesh.tets[0]),
                tetVolume(Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, 4), mesh.tets[0]))
          << trial;
    }
  }
}

// The element Hessian H = -df/dx, projected, has no negative eigenvalue on compressed and
// inverted states (unprojected it does), and always has the three translations in its kernel.
TEST(TeranMuscle, ProjectedElementStiffnessIsPositiveSemiDefinite) {
  std::mt19937 rng(74);
  int indefinite = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const Mesh mesh = randomTet(rng);
    Eigen::VectorXd x = restVector(mesh);
    const double squash = trial < 30 ? 0.4 : -0.3;  // compressed, then inverted
    for (int p = 0; p < 4; ++p) x[3 * p + 2] *= squash;
    x += perturbed(mesh, 0.05 * 0.01, rng) - restVector(mesh);
    TeranMuscleLaw::Constants k;
    k.activation = 0.8;
    k.deviatoricStretch = trial % 2 == 0;
    const HyperelasticModel<TeranMuscleLaw> plain(mesh, {k}, {0.25, false});
    const HyperelasticModel<TeranMuscleLaw> projected(mesh, {k}, {0.25, true});
    const Eigen::MatrixXd H = -testutil::denseStiffness(plain, mesh, x);
    const Eigen::MatrixXd Hp = -testutil::denseStiffness(projected, mesh, x);
    const Eigen::VectorXd l = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H).eigenvalues();
    const Eigen::VectorXd lp = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Hp).eigenvalues();
    indefinite += l.minCoeff() < -1e-9 * l.cwiseAbs().maxCoeff();
    EXPECT_GE(lp.minCoeff(), -1e-12 * lp.cwiseAbs().maxCoeff()) << trial;
    Eigen::VectorXd translation = Eigen::VectorXd::Zero(12);
    for (int p = 0; p < 4; ++p) translation[3 * p] = 1.0;
    EXPECT_LT((Hp * translation).norm(), 1e-9 * Hp.norm());
  }
  EXPECT_GT(indefinite, 10) << "the unprojected samples should include indefinite Hessians";
}

// The split for fitting (Eq. 4): f_0 + sum_m alpha_m f_m is the force of the law at the
// activations alpha, per material, on a plain and on an inverted state.
TEST(TeranMuscle, ActivationForcesSplitTheForceByMuscle) {
  std::mt19937 rng(75);
  const Mesh mesh = testutil::boxMesh(2, 2, 2, 0.01, rng);  // materials 0 and 1
  std::vector<TeranMuscleLaw::Constants> k(2);
  k[1].A = 2e4, k[1].sigmaMax = 1e5, k[1].deviatoricStretch = false;
  const LawOptions options{0.25, false};
  const MuscleActivationForces split(mesh, k, options);
  ASSERT_EQ(split.numMuscles(), 2);
  for (double squash : {1.0, -0.2}) {
    Eigen::VectorXd x = perturbed(mesh, 0.1 * 0.01, rng);
    for (int n = 0; n < mesh.numNodes(); ++n) x[3 * n + 2] *= squash;
    for (const std::vector<double>& alpha : {std::vector<double>{0.3, 0.0},
                                             std::vector<double>{0.0, 0.8},
                                             std::vector<double>{0.55, 0.2}}) {
      std::vector<TeranMuscleLaw::Constants> at = k;
      for (int m = 0; m < 2; ++m) at[m].activation = alpha[m];
      const Eigen::VectorXd f = force(HyperelasticModel<TeranMuscleLaw>(mesh, at, options), x);
      ASSERT_TRUE(f.allFinite());
      EXPECT_LT((split.totalForce(x, alpha) - f).lpNorm<Eigen::Infinity>(),
                1e-12 * f.lpNorm<Eigen::Infinity>())
          << alpha[0] << " " << alpha[1] << " squash " << squash;
    }
    for (int m = 0; m < 2; ++m) EXPECT_GT(split.activationForce(m, x).norm(), 0.0);
  }
}

}  // namespace
}  // namespace tt
