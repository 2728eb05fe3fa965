// The law guccione (material/guccione.h) against the benchmark's formula written out by hand
// (Land et al., "Verification of cardiac mechanics software: benchmark problems and solutions
// for testing active and passive material behaviour", Sec. 2b), and against a closed-form
// uniaxial stress; the finite-difference checks are the conformance suite's.
#include <gtest/gtest.h>

#include <cmath>

#include "tissue_trainer/core/material/guccione.h"

namespace tt {
namespace {

// Q of the paper, each strain component named: fibre f = x, sheet s = y, normal n = z.
double paperExponent(const GuccioneConstants& c, const Eigen::Matrix3d& F) {
  const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
  const double Eff = E(0, 0), Ess = E(1, 1), Enn = E(2, 2);
  const double Efs = E(0, 1), Esf = E(1, 0), Efn = E(0, 2), Enf = E(2, 0);
  const double Esn = E(1, 2), Ens = E(2, 1);
  return c.bf * Eff * Eff + c.bt * (Ess * Ess + Enn * Enn + Esn * Esn + Ens * Ens) +
         c.bfs * (Efs * Efs + Esf * Esf + Efn * Efn + Enf * Enf);
}

TEST(GuccioneLaw, EnergyIsThePapersFormulaPlusThePenalty) {
  const GuccioneConstants c{2000.0, 8.0, 2.0, 4.0, 3e4};
  const GuccioneLaw::Parameters p = GuccioneLaw::parameters(c, Eigen::Matrix3d::Identity());
  Eigen::Matrix3d F;
  F << 1.1, 0.2, -0.05, 0.03, 0.95, 0.1, 0.02, -0.04, 1.02;
  const double J = F.determinant();
  const double expected =
      0.5 * c.C * (std::exp(paperExponent(c, F)) - 1.0) + 0.5 * c.bulkModulus * (J - 1) * (J - 1);
  EXPECT_NEAR(GuccioneLaw::energy(p, F), expected, 1e-12 * expected);
}

// The fibre frame turns the law: the fibre along y makes b_f act on E_yy.
TEST(GuccioneLaw, FibreFrameSelectsTheStiffDirection) {
  const GuccioneConstants c{2000.0, 8.0, 2.0, 4.0, 0.0};
  Eigen::Matrix3d alongY;
  alongY << 0, 1, 0, 1, 0, 0, 0, 0, -1;  // fibre y, sheet x, normal -z
  const GuccioneLaw::Parameters p = GuccioneLaw::parameters(c, alongY);
  const Eigen::Matrix3d stretchY = Eigen::Vector3d(1.0, 1.1, 1.0).asDiagonal();
  const double Eyy = 0.5 * (1.1 * 1.1 - 1.0);
  EXPECT_NEAR(GuccioneLaw::energy(p, stretchY), 0.5 * c.C * std::expm1(c.bf * Eyy * Eyy), 1e-9);
}

// F = diag(l, 1, 1) along the fibre: E_ff = (l^2 - 1)/2, Q = b_f E_ff^2,
// P_11 = l C e^Q b_f E_ff + kappa (l - 1) (cof F = diag(1, l, l)), P_22 = kappa (l - 1) l.
TEST(GuccioneLaw, UniaxialStretchStressInClosedForm) {
  const GuccioneConstants c{2000.0, 8.0, 2.0, 4.0, 3e4};
  const GuccioneLaw::Parameters p = GuccioneLaw::parameters(c, Eigen::Matrix3d::Identity());
  for (double l : {0.9, 1.05, 1.2}) {
    const Eigen::Matrix3d P = GuccioneLaw::stress(p, Eigen::Vector3d(l, 1, 1).asDiagonal());
    const double E = 0.5 * (l * l - 1.0);
    const double P11 = l * c.C * std::exp(c.bf * E * E) * c.bf * E + c.bulkModulus * (l - 1.0);
    EXPECT_NEAR(P(0, 0), P11, 1e-10 * std::abs(P11)) << l;
    EXPECT_NEAR(P(1, 1), c.bulkModulus * (l - 1.0) * l, 1e-8) << l;
    EXPECT_NEAR(P(0, 1), 0.0, 1e-9);
  }
}

// Small strain: psi ~ C/2 Q + kappa/2 (J - 1)^2;
// a simple shear gamma in the fibre-sheet plane (E_fs = E_sf = gamma/2, Q = b_fs gamma^2 / 2
// to second order) costs C b_fs gamma^2 / 4 per volume.
TEST(GuccioneLaw, SmallShearCostsTheFibreSheetWeight) {
  const GuccioneConstants c{2000.0, 8.0, 2.0, 4.0, 3e4};
  const GuccioneLaw::Parameters p = GuccioneLaw::parameters(c, Eigen::Matrix3d::Identity());
  const double g = 1e-4;
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 1) = g;  // E_fs = E_sf = g/2, J = 1
  EXPECT_NEAR(GuccioneLaw::energy(p, F), 0.25 * c.C * c.bfs * g * g, 1e-6 * c.C * g * g);
}

}  // namespace
}  // namespace tt
