// tt::FrameMeter, the simulation node's status measurements in one pass: at any state it gives
// what measureFrame and measureStrain give (each computes everything from the rest positions
// again), and a rigid translation gives its own answers (volume and strain unchanged, every
// node displaced by the translation, the barycentre moved by it).
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include "scene_test_util.h"
#include "tissue_trainer/core/scene/frame_meter.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

// A 3 x 3 x 5-node block of tets under gravity (the strain tests' kind of scene).
const char* const kMeteredBlock = R"(name: metered
mesh: {generator: box, nodes: [3, 3, 5], size: [0.02, 0.02, 0.04], split: six}
materials: [{young_modulus: 3000, poisson_ratio: 0.4, density: 1000}]
force_models: [{type: edge_length}]
integrator: {type: backward_euler}
loads: {gravity: [0, 0, -9.81]}
run: {frame_time: 0.01, duration: 0.1}
)";

Scene block() { return loadScene(testutil::writeScene("metered.yaml", kMeteredBlock)); }

TEST(FrameMeter, GivesWhatMeasureFrameAndMeasureStrainGive) {
  Scene scene = block();
  System& s = scene.system;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.004, 0.004);
  for (Eigen::Index i = 0; i < s.state.x.size(); ++i) {
    s.state.x[i] += jitter(random);
    s.state.v[i] = 100.0 * jitter(random);
  }
  // One tet inverted: its first node moved through the opposite face.
  const Tet& t = s.mesh.tets[3];
  const Eigen::Vector3d face = (s.state.x.segment<3>(3 * t[1]) + s.state.x.segment<3>(3 * t[2]) +
                                s.state.x.segment<3>(3 * t[3])) / 3.0;
  s.state.x.segment<3>(3 * t[0]) += 2.0 * (face - s.state.x.segment<3>(3 * t[0]));
  s.state.t = 0.25;
  StepReport step;
  step.linearIterations = 17;

  // A damage threshold half the largest strain: some tets above it, some below.
  const double damage = 0.5 * measureStrain(s.mesh, s.state.x, 1e9).maxStrain;
  const FrameMeter meter(s);
  const FrameStatus got = meter.measure(s, 12, step, damage);
  const FrameLog want = measureFrame(s, 12, step);
  const StrainSummary wantStrain = measureStrain(s.mesh, s.state.x, damage);
  EXPECT_EQ(got.frame.frame, 12);
  EXPECT_EQ(got.frame.time, 0.25);
  EXPECT_EQ(got.frame.step.linearIterations, 17);
  EXPECT_NEAR(got.frame.kineticEnergy, want.kineticEnergy, 1e-12 * want.kineticEnergy);
  EXPECT_NEAR(got.frame.elasticEnergy, want.elasticEnergy, 1e-12 * want.elasticEnergy);
  EXPECT_NEAR(got.frame.loadEnergy, want.loadEnergy, 1e-12 * std::abs(want.loadEnergy));
  EXPECT_NEAR(got.frame.volume, want.volume, 1e-12 * want.volume);
  EXPECT_NEAR(got.frame.volumeRatio, want.volumeRatio, 1e-12);
  EXPECT_NEAR(got.frame.maxDisplacement, want.maxDisplacement, 1e-15);
  EXPECT_LT((got.frame.barycentre - want.barycentre).norm(), 1e-15);
  EXPECT_GT(wantStrain.strainedTets, 0);
  EXPECT_LT(wantStrain.strainedTets, s.mesh.numTets());
  EXPECT_NEAR(got.strain.maxStrain, wantStrain.maxStrain, 1e-12 * wantStrain.maxStrain);
  EXPECT_EQ(got.strain.strainedTets, wantStrain.strainedTets);
  EXPECT_NEAR(got.strain.strainedVolume, wantStrain.strainedVolume, 1e-12 * wantStrain.strainedVolume);
}

TEST(FrameMeter, RigidTranslationMovesOnlyTheDisplacementAndTheBarycentre) {
  Scene scene = block();
  System& s = scene.system;
  const FrameMeter meter(s);
  const FrameStatus rest = meter.measure(s, 0, {}, 0.05);
  EXPECT_NEAR(rest.frame.volume, 0.02 * 0.02 * 0.04, 1e-18);
  EXPECT_NEAR(rest.frame.volumeRatio, 1.0, 1e-14);
  EXPECT_EQ(rest.frame.maxDisplacement, 0.0);
  EXPECT_LT((rest.frame.barycentre - Eigen::Vector3d(0.01, 0.01, 0.02)).norm(), 1e-15);
  const Eigen::Vector3d shift(0.003, -0.004, 0.012);  // 13 mm
  for (int a = 0; a < s.numNodes(); ++a) s.state.x.segment<3>(3 * a) += shift;
  const FrameStatus moved = meter.measure(s, 1, {}, 0.05);
  EXPECT_NEAR(moved.frame.volumeRatio, 1.0, 1e-12);
  EXPECT_NEAR(moved.frame.maxDisplacement, 0.013, 1e-15);
  EXPECT_LT((moved.frame.barycentre - rest.frame.barycentre - shift).norm(), 1e-15);
  EXPECT_LT(moved.strain.maxStrain, 1e-12);
  EXPECT_EQ(moved.strain.strainedTets, 0);
}

TEST(FrameMeter, RefusesASystemOfAnotherSize) {
  Scene one = block();
  const Scene other = loadScene(testutil::writeScene(
      "metered_other.yaml", testutil::replaced(kMeteredBlock, "nodes: [3, 3, 5]", "nodes: [3, 3, 4]")));
  const FrameMeter meter(one.system);
  EXPECT_THROW(meter.measure(other.system, 0, {}, 0.05), std::invalid_argument);
}

}  // namespace
}  // namespace tt
