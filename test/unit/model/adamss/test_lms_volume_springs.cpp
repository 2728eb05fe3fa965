// The Adamss adaptive (LMS) volume springs (model/adamss/lms_volume_springs.h): the adapted
// spring drives a squeezed tet's volume error down where the fixed spring of the same initial
// stiffness keeps it, Eq. 2.81 as printed softens a compressed tet, the update repeats for a
// repeated start, and the gradient form's force is minus its energy gradient.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "../../model_test_util.h"
#include "tissue_trainer/core/model/adamss/lms_volume_springs.h"
#include "tissue_trainer/core/model/adamss/volume_springs.h"

namespace tt {
namespace {

using adamss::LmsVolumeSpringModel;
using adamss::LmsVolumeSpringParameters;
using namespace testutil;

// The regular tet with vertices (+-1, +-1, +-1) (an even number of minus signs) times size.
Mesh regularTet(double size) {
  Mesh m;
  m.rest.resize(3, 4);
  m.rest << 1, 1, -1, -1, 1, -1, 1, -1, 1, -1, -1, 1;
  m.rest *= size;
  m.tets = {{0, 1, 2, 3}};
  if (tetVolume(m.rest, m.tets[0]) < 0.0) std::swap(m.tets[0][2], m.tets[0][3]);
  m.fillDefaults();
  return m;
}

// Every node of a regular tet pushed toward the centre by a constant force of 0.01 N, damped
// (critically for k = 10 N/m), integrated by symplectic Euler. The tet stays regular, so the
// spring strain s and the volume error are tied. Returns Delta V / V0 after each step.
std::vector<double> squeeze(ForceModel& model, const Mesh& mesh, int steps) {
  const double h = 1e-4, mass = 1e-3, damping = 0.2, load = 0.01;
  Eigen::VectorXd x = restVector(mesh), v = Eigen::VectorXd::Zero(12), push(12);
  for (int p = 0; p < 4; ++p) push.segment<3>(3 * p) = -load * mesh.rest.col(p).normalized();
  const double v0 = tetVolume(mesh.rest, mesh.tets[0]);
  std::vector<double> errors;
  for (int n = 0; n < steps; ++n) {
    if (model.needsStepUpdates()) model.beginStep(n * h, x, v);
    Eigen::VectorXd f = push - damping * v;
    model.addForce(x, v, f);
    v += (h / mass) * f;
    x += h * v;
    const Eigen::Matrix3Xd now = Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, 4);
    errors.push_back((tetVolume(now, mesh.tets[0]) - v0) / v0);
  }
  return errors;
}

TEST(AdamssLmsVolumeSprings, AdaptationDrivesTheVolumeErrorDownFasterThanTheFixedSpring) {
  const Mesh mesh = regularTet(0.01);
  const int steps = 4000;
  adamss::VolumeSpringModel fixedSpring(mesh, {10.0, 0.0, false});
  LmsVolumeSpringModel adaptive(mesh, {10.0, 3e9, false, false});
  LmsVolumeSpringModel printed(mesh, {10.0, 3e9, true, false});
  const std::vector<double> fixedErrors = squeeze(fixedSpring, mesh, steps);
  const std::vector<double> adaptiveErrors = squeeze(adaptive, mesh, steps);
  const std::vector<double> printedErrors = squeeze(printed, mesh, steps);
  // The fixed spring settles at a compression of a few percent.
  EXPECT_LT(fixedErrors.back(), -0.02);
  EXPECT_NEAR(fixedErrors.back(), fixedErrors[steps / 2], 0.01 * std::abs(fixedErrors.back()));
  // The adaptive one keeps stiffening while the tet is compressed: its error keeps falling.
  EXPECT_GT(adaptive.stiffness(0), 20.0);
  EXPECT_LT(std::abs(adaptiveErrors[steps / 4]), 0.6 * std::abs(fixedErrors[steps / 4]));
  EXPECT_LT(std::abs(adaptiveErrors.back()), 0.8 * std::abs(adaptiveErrors[steps / 4]));
  EXPECT_LT(std::abs(adaptiveErrors.back()), 0.25 * std::abs(fixedErrors.back()));
  // As printed (k += mu dV sum|xi|, dV < 0) the spring softens and the tet loses more volume.
  EXPECT_LT(printed.stiffness(0), 10.0);
  EXPECT_GT(std::abs(printedErrors[steps / 4]), std::abs(fixedErrors[steps / 4]));
}

TEST(AdamssLmsVolumeSprings, TheUpdateRepeatsForARepeatedStart) {
  std::mt19937 rng(11);
  const Mesh mesh = boxMesh(2, 2, 1, 0.01, rng);
  LmsVolumeSpringModel model(mesh, {10.0, 1e10, false, true});
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(3 * mesh.numNodes());
  const Eigen::VectorXd x1 = perturbed(mesh, 1e-3, rng), x2 = perturbed(mesh, 1e-3, rng);
  const auto stiffnesses = [&] {
    std::vector<double> k;
    for (int e = 0; e < mesh.numTets(); ++e) k.push_back(model.stiffness(e));
    return k;
  };
  model.beginStep(0.0, x1, v);
  const std::vector<double> k1 = stiffnesses();
  model.beginStep(0.0, x1, v);  // a rejected step tried again
  EXPECT_EQ(stiffnesses(), k1);
  model.beginStep(0.001, x2, v);
  const std::vector<double> k2 = stiffnesses();
  EXPECT_NE(k2, k1);
  model.beginStep(0.0, x1, v);  // a frame rolled back to its start
  EXPECT_EQ(stiffnesses(), k1);
  model.beginStep(0.001, x2, v);
  EXPECT_EQ(stiffnesses(), k2);
  // Past the ring of kHistory checkpoints: a return to one of the last starts still repeats.
  std::vector<std::vector<double>> after;
  for (int n = 0; n < 100; ++n) {
    model.beginStep(0.002 + 1e-3 * n, n % 2 ? x1 : x2, v);
    after.push_back(stiffnesses());
  }
  model.beginStep(0.002 + 1e-3 * 90, x2, v);  // the state of that start (n even)
  EXPECT_EQ(stiffnesses(), after[90]);
  // Each step adds mu dV s to its start's stiffness.
  double changed = 0.0;
  for (int e = 0; e < mesh.numTets(); ++e) changed = std::max(changed, std::abs(k1[e] - 10.0));
  EXPECT_GT(changed, 1e-6);
}

TEST(AdamssLmsVolumeSprings, GradientFormForceIsMinusTheEnergyGradient) {
  std::mt19937 rng(5);
  const Mesh mesh = boxMesh(2, 1, 1, 0.01, rng);
  LmsVolumeSpringModel model(mesh, {10.0, 1e11, false, true});
  const Eigen::VectorXd x = perturbed(mesh, 1e-3, rng);
  model.beginStep(0.0, x, Eigen::VectorXd::Zero(x.size()));  // unequal stiffnesses
  EXPECT_LT(relDiff(force(model, x), Eigen::VectorXd(-fdGradient(model, x, 1e-7))), 1e-6);
  EXPECT_LT(force(model, restVector(mesh)).lpNorm<Eigen::Infinity>(), 1e-15);
}

TEST(AdamssLmsVolumeSprings, HexahedraAreRefused) {
  Mesh mesh = regularTet(0.01);
  mesh.hexes = {{0, 1, 2, 3, 0, 1, 2, 3}};
  mesh.fillDefaults();
  const LmsVolumeSpringParameters parameters{1.0, 0.0, false, false};
  EXPECT_THROW(LmsVolumeSpringModel(mesh, parameters), std::invalid_argument);
}

}  // namespace
}  // namespace tt
