// Jeffrey, "A non-linear anisotropic Finite Element Method for surgical simulation",
// Eqs 13-18 (displacement-based StVK, anisotropic B, C, D) in both readings of the sign of
// alpha: Eq 5 as printed, and the corrected sign.
#include <gtest/gtest.h>

#include <cstdio>

#include "../model_test_util.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/stvk_displacement.h"

namespace tt {
namespace {

using namespace testutil;

TEST(StvkDisplacement, CorrectSignEqualsStvkKernel) {
  std::mt19937 rng(11);
  double worstForce = 0.0, worstEnergy = 0.0;
  for (int trial = 0; trial < 100; ++trial) {
    Mesh m = randomTet(rng, 0.01);
    // Small displacements, and large ones with a rotation (no large translation).
    const bool large = trial % 2 == 1;
    Eigen::VectorXd x = perturbed(m, (large ? 0.3 : 1e-3) * 0.01, rng);
    if (large) x = rigidMotion(x, randomRotation(rng), Eigen::Vector3d(0.003, 0.0, -0.002));
    StvkDisplacementModel displacement(m, testMaterials());
    EdgeLengthModel kernel(m, testMaterials(), EdgeLengthPath::kFast);
    worstForce = std::max(worstForce, relDiff(force(displacement, x), force(kernel, x)));
    worstEnergy = std::max(worstEnergy, std::abs(displacement.energy(x) / kernel.energy(x) - 1));
  }
  EXPECT_LT(worstForce, 1e-10);
  EXPECT_LT(worstEnergy, 1e-10);
}

TEST(StvkDisplacement, CorrectSignOnAMeshAndItsStiffness) {
  std::mt19937 rng(12);
  Mesh m = boxMesh(2, 2, 1, 0.01, rng);
  StvkDisplacementModel model(m, testMaterials());
  EdgeLengthModel kernel(m, testMaterials());
  const Eigen::VectorXd x = perturbed(m, 0.002, rng);
  EXPECT_LT(relDiff(force(model, x), force(kernel, x)), 1e-10);
  EXPECT_LT(relDiff(force(model, x), Eigen::VectorXd(-fdGradient(model, x, 1e-7))), 1e-6);
  EXPECT_LT(relDiff(denseStiffness(model, m, x), fdForceJacobian(model, x, 1e-7)), 1e-6);
}

// Eq 5 as printed (alpha = -g) computes the StVK force of the point-reflected displacement.
TEST(StvkDisplacement, PrintedSignIsTheReflectedConfiguration) {
  std::mt19937 rng(13);
  Mesh m = boxMesh(2, 1, 1, 0.01, rng);
  StvkDisplacementModel literal(m, testMaterials(), AlphaSign::kPaperLiteral);
  EdgeLengthModel kernel(m, testMaterials());
  const Eigen::VectorXd rest = restVector(m);
  for (double amplitude : {1e-5, 1e-3}) {
    const Eigen::VectorXd x = perturbed(m, amplitude, rng);
    const Eigen::VectorXd reflected = 2.0 * rest - x;
    EXPECT_LT(relDiff(force(literal, x), Eigen::VectorXd(-force(kernel, reflected))), 1e-10);
    EXPECT_NEAR(literal.energy(x), kernel.energy(reflected), 1e-10 * kernel.energy(reflected));
    // Not simply the StVK force at x (the sign matters beyond small strain).
    if (amplitude > 1e-4) EXPECT_GT(relDiff(force(literal, x), force(kernel, x)), 1e-2);
    // Its analytic stiffness is consistent with its own force and energy.
    EXPECT_LT(relDiff(force(literal, x), Eigen::VectorXd(-fdGradient(literal, x, 1e-7))), 1e-6);
    EXPECT_LT(relDiff(denseStiffness(literal, m, x), fdForceJacobian(literal, x, 1e-7)), 1e-6);
  }
}

// The printed sign has spurious rest states and no rotation invariance: x = 2 rest - R rest
// (a rotation of the reflected body) is force-free although it is a 3x stretch when R turns
// 180 degrees about z.
TEST(StvkDisplacement, PrintedSignHasSpuriousRestStates) {
  std::mt19937 rng(14);
  Mesh m = boxMesh(2, 2, 2, 0.01, rng);
  StvkDisplacementModel literal(m, testMaterials(), AlphaSign::kPaperLiteral);
  StvkDisplacementModel correct(m, testMaterials(), AlphaSign::kCorrect);
  const Eigen::VectorXd rest = restVector(m);
  const Eigen::Matrix3d halfTurn = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::VectorXd x = 2.0 * rest - rigidMotion(rest, halfTurn, Eigen::Vector3d::Zero());
  const double stretchedForce = force(correct, x).lpNorm<Eigen::Infinity>();
  EXPECT_GT(stretchedForce, 1.0);
  EXPECT_LT(force(literal, x).lpNorm<Eigen::Infinity>(), 1e-9 * stretchedForce);
  // A rigid rotation of the rest shape is free for the correct sign, not for the printed one.
  const Eigen::VectorXd rotated = rigidMotion(rest, randomRotation(rng), Eigen::Vector3d::Zero());
  EXPECT_LT(force(correct, rotated).lpNorm<Eigen::Infinity>(), 1e-9 * stretchedForce);
  EXPECT_GT(force(literal, rotated).lpNorm<Eigen::Infinity>(), 1e-3 * stretchedForce);
}

// With the corrected sign of alpha the displacement formulation is the StVK polynomial but
// works with U = x - rest, so a large rigid translation costs digits. Measured and printed;
// the reference is the kernel, whose F comes from exact edge differences.
TEST(StvkDisplacement, DigitsLostUnderLargeTranslation) {
  std::mt19937 rng(15);
  Mesh m = boxMesh(2, 2, 2, 0.01, rng);
  StvkDisplacementModel displacement(m, testMaterials());
  EdgeLengthModel kernel(m, testMaterials());
  const Eigen::VectorXd x = perturbed(m, 1e-4, rng);  // about 1% strain
  const Eigen::Vector3d direction = randomUnit(rng);
  std::printf("  translation / element length   max rel. force error (displacement vs kernel)\n");
  double errorAtZero = 0.0, errorAtLargest = 0.0;
  for (double lengths : {0.0, 1.0, 10.0, 100.0, 1e3, 1e4}) {
    const Eigen::VectorXd y = rigidMotion(x, Eigen::Matrix3d::Identity(), lengths * 0.01 * direction);
    const double error = relDiff(force(displacement, y), force(kernel, y));
    std::printf("  %10.0e                     %10.2e\n", lengths, error);
    if (lengths == 0.0) errorAtZero = error;
    errorAtLargest = error;
  }
  EXPECT_LT(errorAtZero, 1e-10);
  EXPECT_GT(errorAtLargest, errorAtZero);  // the loss is real, not a test artefact
}

TEST(StvkDisplacement, SignNamesParse) {
  AlphaSign s;
  ASSERT_TRUE(parseAlphaSign("paper_literal", s));
  EXPECT_EQ(s, AlphaSign::kPaperLiteral);
  ASSERT_TRUE(parseAlphaSign("correct", s));
  EXPECT_EQ(s, AlphaSign::kCorrect);
  EXPECT_FALSE(parseAlphaSign("literal", s));
}

}  // namespace
}  // namespace tt
