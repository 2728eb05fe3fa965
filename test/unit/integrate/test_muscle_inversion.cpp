// A muscle block flattened through itself recovers its rest shape ("Derivation of
// Quasistatics and Landmark Optimization for Muscles", Sec. 4: the inversion handling of the
// Teran muscle; rotation-only SVD with threshold 0.25, PSD-projected stiffness): every free
// node of a block clamped at its base is mirrored through the base plane, so every tet is
// inverted; damped backward Euler brings it back to the equilibrium the quasistatic solver
// finds from the rest shape, and so does the quasistatic solver itself. Newton's line search
// alone finds no decrease there (the force, evaluated at the clamped F, is not the energy's
// gradient); the solver's pseudo-time recovery (equilibrium.h, PseudoTimeRecovery) gets out.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/solve/equilibrium.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace {

// A 2 x 2 x 1 cm muscle block at rest activation 0.2, its base z = 0 clamped, every other node
// mirrored through the base (z -> -z): each tet has the negative of its rest volume.
std::unique_ptr<System> flattenedBlock() {
  Mesh mesh = boxGrid(4, 4, 3, Eigen::Vector3d(0.02, 0.02, 0.01), TetSplit::kSixMirrored);
  auto s = std::make_unique<System>(mesh, std::vector<Material>{Material::isotropic(3e4, 0.45, 1060.0)});
  TeranMuscleLaw::Constants k;
  k.activation = 0.2;
  LawOptions options;
  options.inversionThreshold = 0.25;
  options.psdProjection = true;
  s->models.push_back(std::make_unique<HyperelasticModel<TeranMuscleLaw>>(
      s->mesh, std::vector<TeranMuscleLaw::Constants>{k}, options));
  for (int n = 0; n < s->numNodes(); ++n)
    if (s->mesh.rest(2, n) == 0.0) s->mesh.nodeTags[n] = kFixedAll;
  s->updateConstraints();
  for (int n = 0; n < s->numNodes(); ++n) s->state.x[3 * n + 2] = -s->mesh.rest(2, n);
  return s;
}

double signedVolume6(const Eigen::VectorXd& x, const Tet& t) {
  Eigen::Matrix3d D;
  for (int c = 0; c < 3; ++c) D.col(c) = x.segment<3>(3 * t[c + 1]) - x.segment<3>(3 * t[0]);
  return D.determinant();
}

int invertedTets(const System& s) {
  int inverted = 0;
  for (const Tet& t : s.mesh.tets) inverted += signedVolume6(s.state.x, t) <= 0.0;
  return inverted;
}

// Largest |V_t(x) / V_t(reference) - 1| over the tets.
double worstVolumeRatioError(const System& s, const Eigen::VectorXd& reference) {
  double worst = 0.0;
  for (const Tet& t : s.mesh.tets)
    worst = std::max(worst,
                     std::abs(signedVolume6(s.state.x, t) / signedVolume6(reference, t) - 1.0));
  return worst;
}

// The equilibrium reached from the rest shape (the activation shortens the fibres a little).
Eigen::VectorXd restEquilibrium() {
  auto s = flattenedBlock();
  s->state.x = Eigen::Map<const Eigen::VectorXd>(s->mesh.rest.data(), s->numDofs());
  EXPECT_TRUE(solveEquilibrium(*s).converged());
  return s->state.x;
}

TEST(MuscleInversion, DampedBackwardEulerUnflattensTheBlock) {
  auto s = flattenedBlock();
  ASSERT_EQ(invertedTets(*s), s->mesh.numTets());
  s->damping = 50.0 * s->mass;  // 1/s: the motion dies out within the run
  BackwardEulerIntegrator integrator;
  for (int frame = 0; frame < 200; ++frame)
    ASSERT_TRUE(integrator.advance(*s, 0.01).ok) << "frame " << frame;
  const double error = (s->state.x - restEquilibrium()).lpNorm<Eigen::Infinity>();
  std::printf("[ measured ] backward Euler, 2 s from fully inverted: largest distance from the "
              "rest equilibrium %.3g m\n", error);
  EXPECT_EQ(invertedTets(*s), 0);
  EXPECT_LT(error, 1e-5);
}

// One quasistatic frame from the state of s; the report of its equilibrium solve.
EquilibriumReport quasistaticFrame(System& s, EquilibriumParams params = {}) {
  QuasistaticIntegrator integrator(params);
  const StepReport step = integrator.advance(s, 0.01);
  EXPECT_EQ(step.ok, integrator.lastReport().converged()) << step.failure;
  return integrator.lastReport();
}

void printRecovery(const char* what, const EquilibriumReport& r, double distance,
                   double volume) {
  std::printf("[ measured ] quasistatic, %s: %s, %d Newton steps, %d recoveries, %d pseudo-time "
              "steps (%d refused), %d CG iterations, residual %.3g N; largest distance from the "
              "rest equilibrium %.3g m, largest tet volume ratio error %.3g\n",
              what, stopName(r.stop), r.newtonIterations, r.recoveries, r.pseudoTimeSteps,
              r.rejectedPseudoTimeSteps, r.linearIterations, r.residual, distance, volume);
}

// Tolerances of the recovered shape: the solve from the inverted block stops at |f| <= 1e-9 of
// its initial residual (230 N for the flattened block, so 2.3e-7 N) and the reference at
// 3.3e-9 N; the smallest eigenvalue of -K over the free DOFs at the rest equilibrium is
// 153 N/m, so the two states are within about 2.4e-7 / 153 = 1.5e-9 m of each other: 1e-8 m
// allows for the linearisation. Moving a tet's vertex by d changes its volume by d / h
// relative (h that vertex's height, 4 mm or more in this mesh), so the four vertices within
// 1.5e-9 m change it by 1.5e-6 at most: 1e-5 allows for the same.
constexpr double kDistanceTolerance = 1e-8;
constexpr double kVolumeTolerance = 1e-5;

TEST(MuscleInversion, NewtonAloneFindsNoDecreaseInTheFlattenedBlock) {
  auto s = flattenedBlock();
  EquilibriumParams params;
  params.maxPseudoTimeSteps = 0;
  const EquilibriumReport r = solveEquilibrium(*s, params);
  EXPECT_EQ(r.stop, EquilibriumStop::kLineSearchFailed) << r.reason;
  EXPECT_EQ(r.pseudoTimeSteps, 0);
  EXPECT_GT(invertedTets(*s), 0);
}

TEST(MuscleInversion, QuasistaticUnflattensTheBlock) {
  auto s = flattenedBlock();
  const Eigen::VectorXd reference = restEquilibrium();
  const EquilibriumReport r = quasistaticFrame(*s);
  const double distance = (s->state.x - reference).lpNorm<Eigen::Infinity>();
  const double volume = worstVolumeRatioError(*s, reference);
  printRecovery("fully inverted block", r, distance, volume);
  ASSERT_TRUE(r.converged()) << r.reason;
  EXPECT_GE(r.recoveries, 1);
  EXPECT_GT(r.pseudoTimeSteps, 0);
  EXPECT_EQ(invertedTets(*s), 0);
  EXPECT_LT(distance, kDistanceTolerance);
  EXPECT_LT(volume, kVolumeTolerance);
}

TEST(MuscleInversion, QuasistaticUnfoldsAHalfInvertedBlock) {
  auto s = flattenedBlock();
  // Only the half x >= 1 cm is mirrored; the other half keeps its rest shape.
  for (int n = 0; n < s->numNodes(); ++n)
    if (s->mesh.rest(0, n) < 0.01 - 1e-12) s->state.x[3 * n + 2] = s->mesh.rest(2, n);
  const int inverted = invertedTets(*s);
  ASSERT_GT(inverted, 0);
  ASSERT_LT(inverted, s->mesh.numTets());
  {
    // Newton alone does not converge there: its line search finds no decrease.
    auto newton = flattenedBlock();
    newton->state.x = s->state.x;
    EquilibriumParams off;
    off.maxPseudoTimeSteps = 0;
    const EquilibriumReport r = solveEquilibrium(*newton, off);
    std::printf("[ measured ] half-inverted block, Newton alone: %s after %d Newton steps, "
                "residual %.3g N\n", stopName(r.stop), r.newtonIterations, r.residual);
    EXPECT_FALSE(r.converged());
    EXPECT_GT(invertedTets(*newton), 0);
  }
  const Eigen::VectorXd reference = restEquilibrium();
  const EquilibriumReport r = quasistaticFrame(*s);
  const double distance = (s->state.x - reference).lpNorm<Eigen::Infinity>();
  const double volume = worstVolumeRatioError(*s, reference);
  printRecovery("half-inverted block", r, distance, volume);
  ASSERT_TRUE(r.converged()) << r.reason;
  EXPECT_EQ(invertedTets(*s), 0);
  EXPECT_LT(distance, kDistanceTolerance);
  EXPECT_LT(volume, kVolumeTolerance);
}

TEST(MuscleInversion, QuasistaticUninvertsTheTetsOfACornerPushedThroughAFace) {
  auto s = flattenedBlock();
  s->state.x = restEquilibrium();
  // The top corner node pushed through the opposite face of a tet it belongs to: reflected
  // through the plane of that face, twice the distance.
  int corner = -1;
  for (int n = 0; n < s->numNodes(); ++n)
    if (s->mesh.rest.col(n).isApprox(Eigen::Vector3d(0.02, 0.02, 0.01))) corner = n;
  ASSERT_GE(corner, 0);
  const Tet* tet = nullptr;
  for (const Tet& t : s->mesh.tets)
    if (std::find(t.begin(), t.end(), corner) != t.end()) tet = &t;
  ASSERT_NE(tet, nullptr);
  Eigen::Vector3d face[3];
  int k = 0;
  for (int node : *tet)
    if (node != corner) face[k++] = s->state.x.segment<3>(3 * node);
  const Eigen::Vector3d normal = (face[1] - face[0]).cross(face[2] - face[0]).normalized();
  Eigen::Ref<Eigen::VectorXd> p = s->state.x.segment(3 * corner, 3);
  p -= 2.0 * normal.dot(Eigen::Vector3d(p) - face[0]) * normal;
  ASSERT_GE(invertedTets(*s), 1);
  std::printf("[ measured ] one corner node through the opposite face: %d tet(s) inverted\n",
              invertedTets(*s));
  const Eigen::VectorXd reference = restEquilibrium();
  const EquilibriumReport r = quasistaticFrame(*s);
  const double distance = (s->state.x - reference).lpNorm<Eigen::Infinity>();
  const double volume = worstVolumeRatioError(*s, reference);
  printRecovery("one corner node through the opposite face", r, distance, volume);
  ASSERT_TRUE(r.converged()) << r.reason;
  EXPECT_EQ(invertedTets(*s), 0);
  EXPECT_LT(distance, kDistanceTolerance);
  EXPECT_LT(volume, kVolumeTolerance);
}

// The first pseudo-time steps close to Newton's (a small mass term) take the flattened block
// back to its rest shape whatever that term, from 1e-8 to 1e-2 of the stiffness; short steps
// (a mass term as large as the stiffness, close to the overdamped flow) leave it in a folded
// equilibrium of higher energy, no element inverted or clamped.
TEST(MuscleInversion, FirstPseudoTimeStepsNearNewtonReachTheRestShape) {
  const Eigen::VectorXd reference = restEquilibrium();
  const double restEnergy = flattenedBlock()->potentialEnergy(reference);
  for (double ratio : {1e-8, 1e-5, 1e-2, 0.1, 1.0}) {
    auto s = flattenedBlock();
    EquilibriumParams params;
    params.pseudoTimeInitialRatio = ratio;
    params.maxNewtonIterations = 200;
    const EquilibriumReport r = solveEquilibrium(*s, params);
    const double distance = (s->state.x - reference).lpNorm<Eigen::Infinity>();
    const double energy = s->potentialEnergy(s->state.x);
    std::printf("[ measured ] first mass term %g of the stiffness: %s, %d pseudo-time steps, "
                "%d Newton steps, distance from the rest equilibrium %.3g m, energy %.6g J "
                "(rest equilibrium %.6g J)\n",
                ratio, stopName(r.stop), r.pseudoTimeSteps, r.newtonIterations, distance, energy,
                restEnergy);
    ASSERT_TRUE(r.converged()) << r.reason;
    EXPECT_EQ(invertedTets(*s), 0);
    if (ratio <= 1e-2) {
      EXPECT_LT(distance, kDistanceTolerance) << ratio;
    } else {
      EXPECT_GT(distance, 1e-3);
      EXPECT_GT(energy, restEnergy + 0.1);
    }
  }
}

// With too few pseudo-time steps the solve stops, says why, and a quasistatic frame keeps its
// initial state.
TEST(MuscleInversion, RecoveryOutOfStepsFailsTheFrameCleanly) {
  auto s = flattenedBlock();
  const Eigen::VectorXd before = s->state.x;
  EquilibriumParams params;
  params.maxPseudoTimeSteps = 3;
  QuasistaticIntegrator integrator(params);
  const StepReport step = integrator.advance(*s, 0.01);
  const EquilibriumReport& r = integrator.lastReport();
  EXPECT_FALSE(step.ok);
  EXPECT_EQ(r.stop, EquilibriumStop::kRecoveryFailed);
  EXPECT_EQ(r.pseudoTimeSteps + r.rejectedPseudoTimeSteps, 3);
  EXPECT_NE(step.failure.find("still inverted after 3 pseudo-time steps"), std::string::npos)
      << step.failure;
  EXPECT_EQ(s->state.x, before);
}

// Where Newton's line search always succeeds the recovery is never entered: the same iterates,
// bit for bit, with it and without it.
TEST(MuscleInversion, UninvertedSolveIsTheSameWithAndWithoutTheRecovery) {
  auto with = flattenedBlock();
  with->state.x = Eigen::Map<const Eigen::VectorXd>(with->mesh.rest.data(), with->numDofs());
  for (int n = 0; n < with->numNodes(); ++n) with->state.x[3 * n + 2] *= 1.3;  // stretched
  auto without = flattenedBlock();
  without->state.x = with->state.x;
  EquilibriumParams off;
  off.maxPseudoTimeSteps = 0;
  const EquilibriumReport a = solveEquilibrium(*with);
  const EquilibriumReport b = solveEquilibrium(*without, off);
  ASSERT_TRUE(a.converged()) << a.reason;
  EXPECT_EQ(a.recoveries, 0);
  EXPECT_EQ(a.pseudoTimeSteps, 0);
  EXPECT_EQ(a.newtonIterations, b.newtonIterations);
  EXPECT_EQ(a.residualHistory, b.residualHistory);
  EXPECT_EQ(with->state.x, without->state.x);
}

}  // namespace
}  // namespace tt
