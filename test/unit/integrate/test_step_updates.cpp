// The per-step hook of force models (ForceModel::needsStepUpdates, beginStep): the frame loop
// calls it before every step attempt with the time and state at the step's start, and only for
// the models that ask for it.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "tissue_trainer/core/integrate/explicit_euler.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/registry/registry.h"
#include "oscillators.h"

namespace tt {
namespace {

// A uniform force along x whose magnitude is the time of the step's start, as a time curve of
// active tension would be; it records every call of beginStep.
class StepTimeForce : public ForceModel {
 public:
  explicit StepTimeForce(bool wantsUpdates) : wantsUpdates_(wantsUpdates) {}
  const char* name() const override { return "step_time_force"; }
  double addForce(const Eigen::VectorXd&, const Eigen::VectorXd&,
                  Eigen::VectorXd& f) const override {
    for (Eigen::Index i = 0; i < f.size(); i += 3) f[i] += magnitude_;
    return 0.0;
  }
  double energy(const Eigen::VectorXd&) const override { return 0.0; }
  bool hasEnergy() const override { return false; }
  // A uniform force has no position derivative.
  bool hasStiffness() const override { return true; }
  bool needsStepUpdates() const override { return wantsUpdates_; }
  void beginStep(double t, const Eigen::VectorXd& x, const Eigen::VectorXd&) override {
    magnitude_ = t;
    times.push_back(t);
    firstX.push_back(x[0]);
  }

  std::vector<double> times, firstX;

 private:
  bool wantsUpdates_;
  double magnitude_ = 0.0;
};

System freeTet(std::unique_ptr<StepTimeForce> model) {
  System s(oscillators::unitTet(), {Material::isotropic(1e3, 0.3, 1000.0)});
  s.models.push_back(std::move(model));
  return s;
}

TEST(StepUpdates, CalledAtEveryStepStartWithThatStepsState) {
  auto owned = std::make_unique<StepTimeForce>(true);
  StepTimeForce& model = *owned;
  System s = freeTet(std::move(owned));
  ExplicitEulerIntegrator integrator(ExplicitEulerParams{0.01});
  for (int frame = 0; frame < 2; ++frame) {
    ASSERT_TRUE(integrator.advance(s, 0.05).ok);
  }
  ASSERT_EQ(model.times.size(), 10u);
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(model.times[i], 0.01 * i, 1e-12) << "step " << i;
  // Explicit Euler by hand with the force of each step's start time: v_n+1 = v_n + h t_n / m,
  // x_n+1 = x_n + h v_n. The recorded x of node 0 must be this sequence.
  const double m = s.mass[0], h = 0.01;
  double x = s.mesh.rest(0, 0), v = 0.0;
  for (int i = 0; i < 10; ++i) {
    EXPECT_NEAR(model.firstX[i], x, 1e-14) << "step " << i;
    const double t = h * i;
    x += h * v;
    v += h * t / m;
  }
  EXPECT_NEAR(s.state.x[0], x, 1e-14);
  EXPECT_NEAR(s.state.v[0], v, 1e-14);
}

TEST(StepUpdates, ModelsThatDoNotAskAreNotCalled) {
  auto owned = std::make_unique<StepTimeForce>(false);
  StepTimeForce& model = *owned;
  System s = freeTet(std::move(owned));
  ExplicitEulerIntegrator integrator(ExplicitEulerParams{0.01});
  ASSERT_TRUE(integrator.advance(s, 0.05).ok);
  EXPECT_TRUE(model.times.empty());
  EXPECT_EQ(s.state.v[0], 0.0);  // the magnitude stayed at its initial 0
}

// The quasistatic solve finds the state at a frame's end, so its loads are updated once per
// frame with the end time, not also with the start.
TEST(StepUpdates, QuasistaticUpdatesOncePerFrameAtItsEnd) {
  auto owned = std::make_unique<StepTimeForce>(true);
  StepTimeForce& model = *owned;
  System s = freeTet(std::move(owned));
  for (int n = 0; n < 3; ++n) s.mesh.nodeTags[n] = kFixedAll;
  s.models.push_back(makeElasticModel("tensor_mass", s.mesh, s.materials));
  s.updateConstraints();
  QuasistaticIntegrator integrator;
  for (int frame = 0; frame < 3; ++frame) ASSERT_TRUE(integrator.advance(s, 0.05).ok);
  ASSERT_EQ(model.times.size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(model.times[i], 0.05 * (i + 1), 1e-12) << "frame " << i;
  // Equilibrium of the free node under the last frame's load: it moved along +x.
  EXPECT_GT(s.state.x[9], s.mesh.rest(0, 3));
}

}  // namespace
}  // namespace tt
