// Landmark fitting of activations (fit/landmark_fit.h; Bao, "Derivation of Quasistatics and
// Landmark Optimization for Muscles", Secs. 1-3): the activation Jacobian of Eq. 6 against
// central differences of re-solved equilibria, and activations recovered from landmarks of a
// known equilibrium, from zero, with the cost falling at every step and the bounds kept.
#include <gtest/gtest.h>

#include <cstdio>

#include "fit_test_util.h"

namespace tt {
namespace {

// Central differences of the equilibrium landmark positions, one parameter at a time.
Eigen::MatrixXd centralDifferences(LandmarkFit& fit, const Eigen::VectorXd& theta,
                                   const Eigen::VectorXd& h) {
  Eigen::VectorXd y0, yp, ym;
  EXPECT_TRUE(fit.evaluate(theta, y0));
  Eigen::MatrixXd J(y0.size(), theta.size());
  for (int k = 0; k < theta.size(); ++k) {
    Eigen::VectorXd t = theta;
    t[k] += h[k];
    EXPECT_TRUE(fit.evaluate(t, yp));
    t[k] -= 2 * h[k];
    EXPECT_TRUE(fit.evaluate(t, ym));
    J.col(k) = (yp - ym) / (2 * h[k]);
  }
  return J;
}

TEST(LandmarkFit, ActivationJacobianMatchesCentralDifferencesOfTheEquilibrium) {
  Scene scene = testutil::loadThreeMuscleBlock();
  System& s = scene.system;
  FitParams params;
  params.equilibrium = testutil::tightEquilibrium();
  // Landmarks at every free node and at a tet's centroid.
  std::vector<Landmark> landmarks = testutil::nodeLandmarks(s, s.state.x, 1);
  Landmark centroid;
  centroid.nodes = s.mesh.tets[s.mesh.numTets() - 1];
  centroid.weights = Eigen::Vector4d(0.1, 0.2, 0.3, 0.4);
  landmarks.push_back(centroid);
  LandmarkFit fit(s, landmarks, params);
  ASSERT_EQ(fit.parameterCount(), 3);
  const Eigen::VectorXd theta = Eigen::Vector3d(0.3, 0.5, 0.2);
  Eigen::VectorXd y;
  Eigen::MatrixXd J;
  ASSERT_TRUE(fit.evaluate(theta, y, &J));
  const Eigen::MatrixXd fd = centralDifferences(fit, theta, Eigen::Vector3d::Constant(1e-4));
  for (int k = 0; k < 3; ++k) {
    const double err = (J.col(k) - fd.col(k)).norm() / fd.col(k).norm();
    std::printf("activation %d: |dy/da| = %.4g m, relative error of Eq. 6 %.2e\n", k,
                fd.col(k).norm(), err);
    EXPECT_GT(fd.col(k).norm(), 1e-4);  // every muscle moves the landmarks
    EXPECT_LT(err, 1e-6) << k;
  }
}

struct Recovery {
  Eigen::VectorXd fitted;
  FitResult result;
  std::vector<Eigen::VectorXd> path;  // parameters after each step
};

Recovery recover(const std::vector<double>& truth, double levenbergMarquardt = 0.0) {
  Scene scene = testutil::loadThreeMuscleBlock();
  System& s = scene.system;
  const Eigen::VectorXd rest = s.state.x;
  testutil::setActivations(s, truth);
  EXPECT_TRUE(solveEquilibrium(s, testutil::tightEquilibrium()).converged());
  const std::vector<Landmark> landmarks = testutil::nodeLandmarks(s, s.state.x, 4);
  EXPECT_GE(landmarks.size(), 10u);
  EXPECT_LE(landmarks.size(), 30u);
  testutil::setActivations(s, {0, 0, 0});
  s.state.x = rest;
  FitParams params;
  params.equilibrium = testutil::tightEquilibrium();
  params.residualTolerance = 1e-12;
  params.levenbergMarquardt = levenbergMarquardt;
  LandmarkFit fit(s, landmarks, params);
  Recovery r;
  r.result = fit.run([&](int, const FitIteration&) { r.path.push_back(fit.parameters()); });
  r.fitted = fit.parameters();
  return r;
}

TEST(LandmarkFit, RecoversActivationsFromZeroWithTheCostFallingEveryStep) {
  const std::vector<double> truth = {0.3, 0.6, 0.45};
  const Recovery r = recover(truth);
  EXPECT_TRUE(r.result.converged()) << r.result.reason;
  ASSERT_FALSE(r.result.iterations.empty());
  double previous = 1e300, previousResidual = r.result.initialResidual;
  for (size_t k = 0; k < r.result.iterations.size(); ++k) {
    const FitIteration& it = r.result.iterations[k];
    std::printf("iteration %zu: residual %.3e m, step %.3e\n", k + 1, it.residual, it.step);
    EXPECT_LT(it.cost, previous);
    EXPECT_LT(it.residual, previousResidual);
    previous = it.cost;
    previousResidual = it.residual;
  }
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r.fitted[i], truth[i], 1e-6) << i;
}

TEST(LandmarkFit, ActivationsAtTheirBoundsAreRecoveredWithinTheBounds) {
  const std::vector<double> truth = {0.0, 0.7, 1.0};
  const Recovery r = recover(truth);
  EXPECT_TRUE(r.result.converged()) << r.result.reason;
  for (const Eigen::VectorXd& p : r.path) {
    EXPECT_GE(p.minCoeff(), 0.0);
    EXPECT_LE(p.maxCoeff(), 1.0);
  }
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r.fitted[i], truth[i], 1e-6) << i;
}

TEST(LandmarkFit, LevenbergMarquardtDampingAlsoRecoversTheActivations) {
  const std::vector<double> truth = {0.3, 0.6, 0.45};
  const Recovery plain = recover(truth), damped = recover(truth, 0.1);
  EXPECT_TRUE(damped.result.converged()) << damped.result.reason;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(damped.fitted[i], truth[i], 1e-6) << i;
  // The damping shortens the first step.
  ASSERT_FALSE(damped.result.iterations.empty());
  ASSERT_FALSE(plain.result.iterations.empty());
  EXPECT_LT(damped.result.iterations[0].step, plain.result.iterations[0].step);
  std::printf("iterations: %zu plain, %zu damped (lambda 0.1)\n", plain.result.iterations.size(),
              damped.result.iterations.size());
}

TEST(LandmarkFit, StopsWithTheReasonWhenTheEquilibriumFails) {
  Scene scene = testutil::loadThreeMuscleBlock();
  System& s = scene.system;
  testutil::setActivations(s, {0.3, 0.6, 0.45});
  ASSERT_TRUE(solveEquilibrium(s, testutil::tightEquilibrium()).converged());
  const std::vector<Landmark> landmarks = testutil::nodeLandmarks(s, s.state.x, 4);
  testutil::setActivations(s, {0, 0, 0});
  FitParams params;
  params.equilibrium = testutil::tightEquilibrium();
  params.equilibrium.maxNewtonIterations = 1;  // too few from that state
  LandmarkFit fit(s, landmarks, params);
  const FitResult r = fit.run();
  EXPECT_EQ(r.stop, FitStop::kEquilibriumFailed);
  EXPECT_FALSE(r.converged());
  EXPECT_NE(r.reason.find("the equilibrium did not converge"), std::string::npos) << r.reason;
}

TEST(LandmarkFit, RejectsBadLandmarksJawNodesWithAFreeDofAndSystemsWithoutActivations) {
  Scene scene = testutil::loadThreeMuscleBlock();
  System& s = scene.system;
  std::vector<Landmark> landmarks = testutil::nodeLandmarks(s, s.state.x, 4);
  FitParams params;
  params.fitJaw = true;
  params.jawNodes = {s.numNodes() - 1};  // a top node: free
  EXPECT_THROW(LandmarkFit(s, landmarks, params), std::invalid_argument);
  params.jawNodes = {0};  // a bottom node: fixed
  EXPECT_NO_THROW(LandmarkFit(s, landmarks, params));
  landmarks[0].nodes[2] = s.numNodes();
  EXPECT_THROW(LandmarkFit(s, landmarks, {}), std::invalid_argument);
  EXPECT_THROW(LandmarkFit(s, {}, {}), std::invalid_argument);

  Scene passive = loadScene(testutil::writeScene("passive_block.yaml", R"(name: passive
mesh: {generator: box, nodes: [2, 2, 2], size: [1, 1, 1]}
materials: [{young_modulus: 1, poisson_ratio: 0.3}]
force_models: [{type: hyperelastic, law: neo_hookean}]
integrator: {type: quasistatic}
)"));
  EXPECT_THROW(LandmarkFit(passive.system, testutil::nodeLandmarks(passive.system,
                                                                   passive.system.state.x, 1), {}),
               std::invalid_argument);
}

}  // namespace
}  // namespace tt
