// Jaw and cranium parameters of a landmark fit (fit/landmark_fit.h; Bao, "Derivation of
// Quasistatics and Landmark Optimization for Muscles", Secs. 2.2-2.3 and 3.2-3.4): the jaw
// Jacobian K_ff dx_f/dp = -K_fc dx_c/dp and the cranium post-transform Jacobian against central
// differences of re-solved equilibria, and a known small jaw rotation and translation recovered.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>

#include "fit_test_util.h"

namespace tt {
namespace {

// The jaw: the nodes of the bottom face with x <= 0.01 (fixed on all axes); the rest of the
// bottom face stays fixed.
std::vector<int> jawNodes(const System& s) {
  std::vector<int> out;
  for (int n = 0; n < s.numNodes(); ++n)
    if (std::abs(s.mesh.rest(2, n)) < 1e-9 && s.mesh.rest(0, n) <= 0.01 + 1e-9) out.push_back(n);
  return out;
}

FitParams jawAndCranium(const System& s) {
  FitParams p;
  p.equilibrium = testutil::tightEquilibrium();
  p.fitJaw = true;
  p.jawNodes = jawNodes(s);
  p.fitCranium = true;
  return p;
}

TEST(LandmarkFitJaw, JawAndCraniumJacobiansMatchCentralDifferencesOfTheEquilibrium) {
  Scene scene = testutil::loadThreeMuscleBlock();
  System& s = scene.system;
  LandmarkFit fit(s, testutil::nodeLandmarks(s, s.state.x, 1, true), jawAndCranium(s));
  ASSERT_EQ(fit.parameterCount(), 27);
  // A non-rigid, non-identity point: activations inside, jaw and cranium matrices off identity.
  Eigen::VectorXd theta = fit.parameters();
  theta.head(3) = Eigen::Vector3d(0.3, 0.5, 0.2);
  const double jaw[12] = {1.01, 0.02, -0.01, -0.015, 0.99, 0.005, 0.01, 0.0, 1.0, 1e-4, -2e-4, 1e-4};
  const double cranium[12] = {0.98, 0.1, 0.0, -0.1, 1.0, 0.02, 0.0, -0.03, 1.02, 0.01, 0.0, -0.02};
  for (int k = 0; k < 12; ++k) theta[3 + k] = jaw[k], theta[15 + k] = cranium[k];
  Eigen::VectorXd y, yp, ym;
  Eigen::MatrixXd J;
  ASSERT_TRUE(fit.evaluate(theta, y, &J));
  for (int k = 3; k < 27; ++k) {
    // Entries of M are O(1), of t in m (the block is 2 cm): steps of the same relative size.
    const double h = (k % 12 == 0 || k % 12 == 1 || k % 12 == 2) ? 1e-6 : 1e-4;
    Eigen::VectorXd t = theta;
    t[k] += h;
    ASSERT_TRUE(fit.evaluate(t, yp));
    t[k] -= 2 * h;
    ASSERT_TRUE(fit.evaluate(t, ym));
    const Eigen::VectorXd fd = (yp - ym) / (2 * h);
    if (k < 12 && (k - 3) % 3 == 2) {
      // M_j,i2 multiplies the rest z of the jaw nodes, which is 0: no effect, exactly.
      EXPECT_EQ(fd.norm(), 0.0) << k;
      EXPECT_EQ(J.col(k).norm(), 0.0) << k;
      continue;
    }
    const double err = (J.col(k) - fd).norm() / fd.norm();
    std::printf("%-12s |dy/dp| = %.4g, relative error %.2e\n", fit.parameterName(k).c_str(),
                fd.norm(), err);
    EXPECT_GT(fd.norm(), 0.0) << k;
    EXPECT_LT(err, 1e-6) << fit.parameterName(k);
  }
}

// Back to zero activations at the rest shape, with the tight fit both recoveries use.
FitParams restartedFit(System& s, const Eigen::VectorXd& rest) {
  testutil::setActivations(s, {0, 0, 0});
  s.state.x = rest;
  FitParams params;
  params.equilibrium = testutil::tightEquilibrium();
  params.residualTolerance = 1e-12;
  return params;
}

// Runs the fit; it converges and finds the activations `truth`.
void expectActivationsRecovered(LandmarkFit& fit, const std::vector<double>& truth) {
  const FitResult r = fit.run();
  std::printf("%zu iterations, residual %.3e m (%s)\n", r.iterations.size(), r.residual,
              stopName(r.stop));
  EXPECT_TRUE(r.converged()) << r.reason;
  const Eigen::VectorXd p = fit.parameters();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(p[i], truth[i], 1e-6) << i;
}

TEST(LandmarkFitJaw, RecoversAKnownSmallJawRotationAndTranslation) {
  Scene scene = testutil::loadThreeMuscleBlock();
  System& s = scene.system;
  const Eigen::VectorXd rest = s.state.x;
  const std::vector<int> jaw = jawNodes(s);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.03, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(4e-4, -3e-4, 2e-4);
  const std::vector<double> truth = {0.3, 0.5, 0.2};
  testutil::setActivations(s, truth);
  for (int n : jaw) s.state.x.segment<3>(3 * n) = R * rest.segment<3>(3 * n) + t;
  ASSERT_TRUE(solveEquilibrium(s, testutil::tightEquilibrium()).converged());
  const std::vector<Landmark> landmarks = testutil::nodeLandmarks(s, s.state.x, 3, true);

  FitParams params = restartedFit(s, rest);
  params.fitJaw = true;
  params.jawNodes = jaw;
  LandmarkFit fit(s, landmarks, params);
  expectActivationsRecovered(fit, truth);
  EXPECT_LT((fit.jawMatrix() - R).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((fit.jawTranslation() - t).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(LandmarkFitJaw, RecoversAKnownCraniumRotationAndTranslation) {
  Scene scene = testutil::loadThreeMuscleBlock();
  System& s = scene.system;
  const Eigen::VectorXd rest = s.state.x;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.05, Eigen::Vector3d(-2, 1, 1).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(1e-3, 2e-3, -5e-4);
  const std::vector<double> truth = {0.3, 0.5, 0.2};
  testutil::setActivations(s, truth);
  ASSERT_TRUE(solveEquilibrium(s, testutil::tightEquilibrium()).converged());
  std::vector<Landmark> landmarks = testutil::nodeLandmarks(s, s.state.x, 3, true);
  for (Landmark& l : landmarks) l.target = R * l.target + t;

  FitParams params = restartedFit(s, rest);
  params.fitCranium = true;
  LandmarkFit fit(s, landmarks, params);
  expectActivationsRecovered(fit, truth);
  EXPECT_LT((fit.craniumMatrix() - R).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((fit.craniumTranslation() - t).cwiseAbs().maxCoeff(), 1e-8);
  // The fitted state carries the post-transform.
  const Eigen::VectorXd x = fit.fittedPositions();
  EXPECT_LT((x.segment<3>(3 * landmarks[5].nodes[0]) - landmarks[5].target).norm(), 1e-9);
}

}  // namespace
}  // namespace tt
