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

#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/equilibrium.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/hyperelastic.h"
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

// Tolerances of the recovered shape: the solve stops at |f| <= 1e-9 N, and the smallest
// stiffness of the clamped block is far above 1e-1 N/m, so the nodes are within 1e-8 m of the
// rest equilibrium (1e-6 of the block's thickness) and each tet's volume within 1e-5 of its
// volume there (a 1e-8 m move of a node of a 5 mm tet changes its volume by ~1e-5 relative at
// most).
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

TEST(MuscleInversion, QuasistaticUninvertsOneTet) {
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
