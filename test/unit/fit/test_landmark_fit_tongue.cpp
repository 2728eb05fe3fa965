// The tongue of config/scenes/tongue_muscles.yaml fitted from the EMA-like markers of
// config/scenes/tongue_ema_landmarks.txt (docs/muscles.md, "Fitting the tongue"): the file's
// targets are the scene's equilibrium at known activations, and a fit from zero recovers them.
#include <gtest/gtest.h>

#include <cstdio>

#include "fit_test_util.h"

namespace tt {
namespace {

const char* const kMuscles[3] = {"superior_longitudinal", "transverse", "genioglossus"};
const Eigen::Vector3d kTruth(0.1, 0.4, 0.3);  // the activations the targets file was taken at

void setTongueActivations(System& s, const Eigen::Vector3d& a) {
  for (int i = 0; i < 3; ++i) {
    const ActivationRef ref = s.findActivation(kMuscles[i]);
    ASSERT_NE(ref.model, nullptr) << kMuscles[i];
    ref.model->setActivation(ref.index, a[i]);
  }
}

Eigen::Vector3d landmarkPosition(const Landmark& l, const Eigen::VectorXd& x) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) p += l.weights[k] * x.segment<3>(3 * l.nodes[k]);
  return p;
}

TEST(LandmarkFitTongue, RecoversTheActivationsFromNoiseFreeEmaMarkers) {
  Scene scene = loadScene(std::string(TT_SOURCE_DIR) + "/config/scenes/tongue_muscles.yaml");
  System& s = scene.system;
  std::vector<Landmark> landmarks = readLandmarks(
      std::string(TT_SOURCE_DIR) + "/config/scenes/tongue_ema_landmarks.txt", s.mesh);
  ASSERT_GE(landmarks.size(), 6u);
  const Eigen::VectorXd rest = s.state.x;

  // The truth's equilibrium puts the markers at the file's targets (written to 1e-9 m).
  setTongueActivations(s, kTruth);
  const EquilibriumParams eq = testutil::tightEquilibrium();
  ASSERT_TRUE(solveEquilibrium(s, eq).converged());
  for (Landmark& l : landmarks) {
    const Eigen::Vector3d y = landmarkPosition(l, s.state.x);
    EXPECT_LT((y - l.target).norm(), 1e-8) << "node " << l.nodes[0];
    EXPECT_GT((y - landmarkPosition(l, rest)).norm(), 5e-4) << "node " << l.nodes[0];  // moved
    l.target = y;
  }

  // From zero activations at the rest shape.
  setTongueActivations(s, Eigen::Vector3d::Zero());
  s.state.x = rest;
  FitParams params;
  params.equilibrium = eq;
  params.residualTolerance = 1e-10;
  params.stepTolerance = 1e-9;
  params.maxIterations = 10;
  LandmarkFit fit(s, landmarks, params);
  const FitResult r = fit.run();
  EXPECT_TRUE(r.converged()) << r.reason;
  const Eigen::VectorXd a = fit.parameters();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], kTruth[i], 1e-6) << kMuscles[i];
  std::printf("%zu iterations, RMS residual %.3e m\n", r.iterations.size(), r.residual);
  EXPECT_LT(r.residual, 1e-9);
  for (size_t k = 1; k < r.iterations.size(); ++k)
    EXPECT_LT(r.iterations[k].cost, r.iterations[k - 1].cost) << k;
}

}  // namespace
}  // namespace tt
