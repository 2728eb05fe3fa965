// adamss_active_tension in a scene: the keys reach the model, the curve (in its stress unit)
// drives the tension through the frame loop, and backward Euler runs it.
#include <gtest/gtest.h>

#include <string>

#include "scene_test_util.h"
#include "tissue_trainer/core/model/adamss/active_tension.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

const char* const kActiveScene = R"(name: active_box
mesh: {generator: box, nodes: [3, 2, 2], size: [0.02, 0.01, 0.01], split: six_mirrored}
materials:
  - {young_modulus: 30, poisson_ratio: 0.3, stress_unit: kPa}
fibres: {direction: [1, 0, 0]}
force_models:
  - type: hyperelastic
    law: stvk
  - type: adamss_active_tension
    form: anisotropic
    mode: force
    stress_unit: kPa
    curve: {type: twitch, period: 0.2, peak: 2, rise_time: 0.05, decay_time: 0.1}
integrator: {type: backward_euler}
loads: {rayleigh_mass: 200}
run: {frame_time: 0.005, duration: 0.2}
)";

const adamss::ActiveTensionModel& activeModel(const Scene& scene) {
  const auto* model =
      dynamic_cast<const adamss::ActiveTensionModel*>(scene.system.models.at(1).get());
  EXPECT_NE(model, nullptr);
  return *model;
}

TEST(AdamssActiveTensionScene, KeysReachTheModel) {
  const Scene scene = loadScene(testutil::writeScene("active.yaml", kActiveScene));
  ASSERT_EQ(scene.system.models.size(), 2u);
  const adamss::ActiveTensionModel& model = activeModel(scene);
  EXPECT_EQ(model.form(), adamss::ActiveForm::kAnisotropic);
  EXPECT_EQ(model.mode(), adamss::ActiveMode::kForce);
  EXPECT_TRUE(model.needsStepUpdates());

  const std::string iso = testutil::replaced(
      testutil::replaced(kActiveScene, "form: anisotropic", "form: isotropic"),
      "    mode: force\n", "");
  const Scene isoScene = loadScene(testutil::writeScene("active_iso.yaml", iso));
  EXPECT_EQ(activeModel(isoScene).form(), adamss::ActiveForm::kIsotropic);
  EXPECT_EQ(activeModel(isoScene).mode(), adamss::ActiveMode::kTension);  // the default
}

// The twitch in kPa: 2e3 Pa at its peak (t = 0.05), half of it at t = 0.025 and 0.1, nothing
// after t = 0.15; the frame loop hands each frame's start time to the model.
TEST(AdamssActiveTensionScene, TheTwitchDrivesTheTensionInARun) {
  Scene scene = loadScene(testutil::writeScene("active_run.yaml", kActiveScene));
  const adamss::ActiveTensionModel& model = activeModel(scene);
  const TimeCurve twitch = [] {
    TimeCurve::Twitch w;
    w.period = 0.2;
    w.peak = 2e3;
    w.riseTime = 0.05;
    w.decayTime = 0.1;
    return TimeCurve::twitch(w);
  }();
  double shortest = 0.02;
  for (int frame = 0; frame < 40; ++frame) {
    const double start = scene.system.state.t;
    ASSERT_TRUE(scene.integrator->advance(scene.system, scene.frameTime).ok) << frame;
    EXPECT_NEAR(model.tension(), twitch.value(start), 1e-9) << start;
    const Eigen::Map<const Eigen::Matrix3Xd> x(scene.system.state.x.data(), 3,
                                               scene.system.numNodes());
    shortest = std::min(shortest, x.row(0).maxCoeff() - x.row(0).minCoeff());
  }
  EXPECT_NEAR(model.tension(), twitch.value(0.195), 1e-9);
  EXPECT_LT(shortest, 0.02 * 0.99);  // the twitch shortened the box by more than 1 %
}

// config/scenes/muscle_twitch.yaml: the strip fixed at x = 0 shortens during the twitch (its
// free end moves back by close to t / E of the length at the peak) and is back at rest before
// the next twitch.
TEST(AdamssActiveTensionScene, TheMuscleTwitchSceneContractsAndRelaxes) {
  Scene scene = loadScene(std::string(TT_SOURCE_DIR) + "/config/scenes/muscle_twitch.yaml");
  const Eigen::VectorXd X = scene.system.state.x;
  double largestShortening = 0.0;
  for (int frame = 0; frame < 100; ++frame) {
    ASSERT_TRUE(scene.integrator->advance(scene.system, scene.frameTime).ok) << frame;
    const Eigen::Map<const Eigen::Matrix3Xd> x(scene.system.state.x.data(), 3,
                                               scene.system.numNodes());
    largestShortening = std::max(largestShortening, 0.08 - x.row(0).maxCoeff());
  }
  EXPECT_GT(largestShortening, 0.5 * 0.1 * 0.08);  // t / E = 3 kPa / 30 kPa
  EXPECT_LT(largestShortening, 1.5 * 0.1 * 0.08);
  EXPECT_LT((scene.system.state.x - X).lpNorm<Eigen::Infinity>(), 1e-6);  // at rest at t = 1 s
}

}  // namespace
}  // namespace tt
