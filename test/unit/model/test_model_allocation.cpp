// The per-element loops of the tet models (force, energy, stiffness assembly) allocate
// nothing: global operator new is counted while a model evaluates. The step loops of the abm3
// and rk4_adaptive integrators are checked here too (the counter can live in one file only).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>

#include "../model_test_util.h"
#include "tissue_trainer/core/integrate/abm3.h"
#include "tissue_trainer/core/integrate/rk4_adaptive.h"
#include "tissue_trainer/core/model/adamss/active_tension.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/gravity.h"
#include "tissue_trainer/core/model/stvk_displacement.h"
#include "tissue_trainer/core/model/tensor_mass.h"
#include "tissue_trainer/core/model/adamss/cavity.h"
#include "tissue_trainer/core/model/adamss/lms_volume_springs.h"
#include "tissue_trainer/core/model/collision.h"

// malloc is interposed (operator new and Eigen's aligned_malloc both end in it) and forwards
// to glibc; memory is still released by glibc's free. Not under AddressSanitizer, which owns
// malloc itself.
#if defined(__SANITIZE_ADDRESS__)
#define TT_COUNT_MALLOC 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TT_COUNT_MALLOC 0
#endif
#endif
#if !defined(TT_COUNT_MALLOC) && defined(__GLIBC__)
#define TT_COUNT_MALLOC 1
#endif

namespace {
std::atomic<bool> countingAllocations{false};
std::atomic<long> allocationCount{0};
}  // namespace

#if TT_COUNT_MALLOC
extern "C" void* __libc_malloc(std::size_t size);
extern "C" void* malloc(std::size_t size) {
  if (countingAllocations.load(std::memory_order_relaxed)) ++allocationCount;
  return __libc_malloc(size);
}
#endif

namespace tt {
namespace {

using namespace testutil;

long allocationsDuring(const std::function<void()>& run) {
  allocationCount = 0;
  countingAllocations = true;
  run();
  countingAllocations = false;
  return allocationCount;
}

TEST(ModelAllocation, EvaluationLoopsDoNotAllocate) {
#if !TT_COUNT_MALLOC
  GTEST_SKIP() << "malloc is not countable in this build";
#endif
  std::mt19937 rng(51);
  Mesh m = boxMesh(3, 3, 2, 0.01, rng);
  const auto mats = testMaterials();
  std::vector<std::unique_ptr<ForceModel>> models;
  models.push_back(std::make_unique<EdgeLengthModel>(m, mats, EdgeLengthPath::kFast));
  models.push_back(std::make_unique<EdgeLengthModel>(m, mats, EdgeLengthPath::kLiteral));
  models.push_back(std::make_unique<EdgeLengthModel>(m, mats, EdgeLengthPath::kEq30));
  models.push_back(std::make_unique<StvkDisplacementModel>(m, mats, AlphaSign::kCorrect));
  models.push_back(std::make_unique<StvkDisplacementModel>(m, mats, AlphaSign::kPaperLiteral));
  models.push_back(std::make_unique<TensorMassModel>(m, mats));
  models.push_back(std::make_unique<GravityModel>(Eigen::VectorXd::Ones(3 * m.numNodes()),
                                                  Eigen::Vector3d(0, 0, -9.81)));
  TimeCurve::Twitch twitch;
  twitch.peak = 1e4;
  for (auto form : {adamss::ActiveForm::kAnisotropic, adamss::ActiveForm::kIsotropic})
    for (auto mode : {adamss::ActiveMode::kTension, adamss::ActiveMode::kForce})
      models.push_back(std::make_unique<adamss::ActiveTensionModel>(m, form, mode,
                                                                    TimeCurve::twitch(twitch)));
  {
    // A plane and a sphere through the box and a closed surface (a tet) around a corner.
    Eigen::Matrix3Xd corner(3, 4);
    corner << -0.01, 0.02, -0.01, -0.01, -0.01, -0.01, 0.02, -0.01, -0.01, -0.01, -0.01, 0.02;
    std::vector<ClosedSurface> surfaces;
    surfaces.emplace_back(corner, std::vector<Triangle>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
    CollisionBody mesh;
    mesh.kind = CollisionBody::Kind::kMesh;
    mesh.surface = 0;
    std::vector<int> all(m.numNodes());
    for (int i = 0; i < m.numNodes(); ++i) all[i] = i;
    models.push_back(std::make_unique<CollisionModel>(
        m.numNodes(), all, 100.0,
        std::vector<CollisionBody>{CollisionBody::plane(Eigen::Vector3d(0, 0, 0.01), Eigen::Vector3d(0, 0, 1)),
                                   CollisionBody::sphere(Eigen::Vector3d(0.03, 0.03, 0.02), 0.01), mesh},
        std::move(surfaces), false));
  }
  const Eigen::VectorXd x = perturbed(m, 0.001, rng), v = Eigen::VectorXd::Zero(x.size());
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  SparsePattern pattern(m.numNodes(), m.tets);
  SparseMatrix K = pattern.zeroMatrix();
  // The counter itself works.
  EXPECT_GT(allocationsDuring([&] { Eigen::VectorXd copy = x; f += copy; }), 0);
  for (const auto& model : models) {
    EXPECT_EQ(allocationsDuring([&] { model->beginStep(0.05, x, v); }), 0) << model->name();
    EXPECT_EQ(allocationsDuring([&] { model->addForce(x, v, f); }), 0) << model->name();
    EXPECT_EQ(allocationsDuring([&] { model->energy(x); }), 0) << model->name();
    EXPECT_EQ(allocationsDuring([&] { model->addStiffness(x, 0.5, pattern, K); }), 0)
        << model->name();
  }
}

// The Adamss cavity (over the box's boundary) and the adaptive volume springs: their
// evaluations and the adaptive springs' step update allocate nothing. The cavity's assembled
// stiffness with a volume penalty gathers dV/dx once per call and is left out.
TEST(ModelAllocation, CavityAndAdaptiveSpringsDoNotAllocate) {
#if !TT_COUNT_MALLOC
  GTEST_SKIP() << "malloc is not countable in this build";
#endif
  std::mt19937 rng(52);
  Mesh m = boxMesh(3, 3, 2, 0.01, rng);
  m.surface = extractSurface(m);
  std::vector<adamss::CavityFacet> facets;
  for (const Triangle& t : m.surface) facets.push_back({t[0], t[1], t[2]});
  const adamss::CavityModel cavity(m.rest, facets, {100.0, 1e9, 1.0});
  const adamss::CavityModel pressureOnly(m.rest, facets, {100.0, 0.0, 1.0});
  adamss::LmsVolumeSpringModel lms(m, {10.0, 1e9, false, true});
  const Eigen::VectorXd x = perturbed(m, 0.001, rng), v = Eigen::VectorXd::Zero(x.size());
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size()), out = f;
  const SparsePattern pattern(m.numNodes(), m.tets, cavity.couplings());
  SparseMatrix K = pattern.zeroMatrix();
  for (const adamss::CavityModel* model : {&cavity, &pressureOnly}) {
    EXPECT_EQ(allocationsDuring([&] { model->addForce(x, v, f); }), 0);
    EXPECT_EQ(allocationsDuring([&] { model->energy(x); }), 0);
    EXPECT_EQ(allocationsDuring([&] { model->addStiffnessTimes(x, x, 0.5, out); }), 0);
  }
  EXPECT_EQ(allocationsDuring([&] { pressureOnly.addStiffness(x, 0.5, pattern, K); }), 0);
  for (int n = 0; n < 70; ++n)  // around the ring of checkpoints
    EXPECT_EQ(allocationsDuring([&] { lms.beginStep(1e-3 * n, x, v); }), 0) << n;
  EXPECT_EQ(allocationsDuring([&] { lms.beginStep(1e-3 * 60, x, v); }), 0);
  EXPECT_EQ(allocationsDuring([&] { lms.addForce(x, v, f); }), 0);
  EXPECT_EQ(allocationsDuring([&] { lms.energy(x); }), 0);
}

// After the first frame sized its buffers, a frame of 40 steps allocates what a frame of one
// step does (the frame loop's copy of the initial state): the steps themselves allocate nothing.
TEST(Abm3Allocation, StepLoopDoesNotAllocateAfterTheFirstStep) {
#if !TT_COUNT_MALLOC
  GTEST_SKIP() << "malloc is not countable in this build";
#endif
  std::mt19937 rng(7);
  const Mesh m = boxMesh(2, 2, 2, 0.01, rng);
  for (bool adaptive : {false, true}) {
    for (auto interpolation :
         {Abm3Params::Interpolation::kLinear, Abm3Params::Interpolation::kHermite}) {
      System s(m, testMaterials());
      s.models.push_back(std::make_unique<TensorMassModel>(s.mesh, s.materials));
      s.state.x = perturbed(m, 0.0005, rng);
      Abm3Params p;
      p.adaptive = adaptive;
      p.timeStep = 1e-5;
      p.interpolation = interpolation;
      Abm3Integrator integrator(p);
      ASSERT_TRUE(integrator.advance(s, 1e-4).ok);
      const long one = allocationsDuring([&] { integrator.advance(s, 1e-5); });
      const long many = allocationsDuring([&] { integrator.advance(s, 4e-4); });
      EXPECT_EQ(many, one) << (adaptive ? "adaptive" : "fixed");
    }
  }
}

// The same for the Runge-Kutta method, adaptive (rejections included: the first frame's step
// is too long for the tolerance) and fixed.
TEST(Rk4AdaptiveAllocation, StepLoopDoesNotAllocateAfterTheFirstStep) {
#if !TT_COUNT_MALLOC
  GTEST_SKIP() << "malloc is not countable in this build";
#endif
  std::mt19937 rng(8);
  const Mesh m = boxMesh(2, 2, 2, 0.01, rng);
  for (bool adaptive : {false, true}) {
    System s(m, testMaterials());
    s.models.push_back(std::make_unique<TensorMassModel>(s.mesh, s.materials));
    s.state.x = perturbed(m, 0.0005, rng);
    Rk4AdaptiveParams p;
    p.adaptive = adaptive;
    p.timeStep = 1e-5;
    Rk4AdaptiveIntegrator integrator(p);
    ASSERT_TRUE(integrator.advance(s, 1e-4).ok);
    const long one = allocationsDuring([&] { integrator.advance(s, 1e-5); });
    const long many = allocationsDuring([&] { integrator.advance(s, 4e-4); });
    EXPECT_EQ(many, one) << (adaptive ? "adaptive" : "fixed");
  }
}

}  // namespace
}  // namespace tt
