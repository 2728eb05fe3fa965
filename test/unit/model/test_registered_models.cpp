// The physics checks on every preset of a registered force model (one model each; the tissue
// presets are checked in test_tissue_presets.cpp), so that a model added to the registry is
// checked without a test file of its own: force against energy and stiffness
// against force by finite differences, a symmetric stiffness, K d against the assembled K, no
// force at rest, invariance under translation and rotation. A preset is exempt from a check
// only where kExempt says why, and checked at smaller motions only where kSmallerMotion says why.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <utility>

#include "../model_test_util.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace {

using namespace testutil;

enum Check { kEnergyGradient, kRotation };

// Presets that do not claim a property, and why.
const std::map<std::string, std::map<Check, const char*>> kExempt = {
    {"stvk_displacement_paper_literal",
     {{kEnergyGradient, "the printed sign of the shape vectors (Jeffrey, Eq. 5): kept to show it is not the gradient"},
      {kRotation, "the printed sign breaks the rotation invariance as well"}}},
    {"tensor_mass", {{kRotation, "linear elasticity: a rotation is a strain to it"}}},
};

// Presets checked at smaller random node motions than the 1e-3 m (10 % of the cells) of the
// others, and why.
const std::map<std::string, std::pair<double, const char*>> kSmallerMotion = {
    {"hyperelastic_hunter",
     {2e-4, "the pole-zero law has no state past its poles (Table 2.1: a fibre Green strain of "
            "0.318), which 10 % random motions reach; hyperelastic_hunter_polynomial has none"}},
};

double motionFor(const std::string& preset) {
  const auto it = kSmallerMotion.find(preset);
  return it == kSmallerMotion.end() ? 1e-3 : it->second.first;
}

bool exempt(const std::string& preset, Check check) {
  const auto it = kExempt.find(preset);
  return it != kExempt.end() && it->second.count(check) > 0;
}

TEST(RegisteredModels, ExemptionsNameRegisteredPresets) {
  const std::vector<std::string> names = registry().presetNames();
  const std::set<std::string> known(names.begin(), names.end());
  for (const auto& [preset, checks] : kExempt) EXPECT_TRUE(known.count(preset)) << preset;
  for (const auto& [preset, motion] : kSmallerMotion) EXPECT_TRUE(known.count(preset)) << preset;
  EXPECT_GE(names.size(), 7u);
}

TEST(RegisteredModels, EveryPresetPassesThePhysicsChecks) {
  std::mt19937 rng(31);
  const Mesh mesh = boxMesh(2, 2, 1, 0.01, rng);
  const std::vector<Material> materials = testMaterials();
  for (const std::string& preset : registry().modelPresetNames()) {
    SCOPED_TRACE(preset);
    const auto model = makeElasticModel(preset, mesh, materials);
    const Eigen::VectorXd rest = restVector(mesh);
    const Eigen::VectorXd x = perturbed(mesh, motionFor(preset), rng);
    const Eigen::VectorXd f = force(*model, x);
    EXPECT_LT(force(*model, rest).lpNorm<Eigen::Infinity>(), 1e-9 * f.lpNorm<Eigen::Infinity>());
    if (model->hasEnergy() && !exempt(preset, kEnergyGradient))
      EXPECT_LT(relDiff(f, Eigen::VectorXd(-fdGradient(*model, x, 1e-7))), 1e-6);
    if (model->hasStiffness()) {
      const Eigen::MatrixXd K = denseStiffness(*model, mesh, x);
      EXPECT_LT(relDiff(K, fdForceJacobian(*model, x, 1e-7)), 1e-6);
      if (!exempt(preset, kEnergyGradient))
        EXPECT_LT(relDiff(Eigen::MatrixXd(K.transpose()), K), 1e-10);
      if (model->hasStiffnessProduct()) {
        const Eigen::VectorXd d = perturbed(mesh, 1.0, rng) - rest;
        Eigen::VectorXd Kd = Eigen::VectorXd::Zero(x.size());
        model->addStiffnessTimes(x, d, 1.0, Kd);
        EXPECT_LT(relDiff(Kd, Eigen::VectorXd(K * d)), 1e-12);
      }
    }
    // A few element lengths: the displacement-form models work on x - X, so a far shift would
    // measure their cancellation error, not an invariance.
    const Eigen::Vector3d shift(0.04, -0.011, 0.023);
    EXPECT_LT(relDiff(force(*model, rigidMotion(x, Eigen::Matrix3d::Identity(), shift)), f), 1e-8);
    if (!exempt(preset, kRotation)) {
      const Eigen::Matrix3d R = randomRotation(rng);
      EXPECT_LT(relDiff(force(*model, rigidMotion(x, R, shift)), rotateVectors(f, R)), 1e-8);
    }
  }
}

}  // namespace
}  // namespace tt
