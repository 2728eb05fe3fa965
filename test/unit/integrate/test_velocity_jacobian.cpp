// Force-model capabilities the implicit integrators and the pattern use: an assembled
// velocity Jacobian df/dv makes a model's damping implicit in backward Euler and enters Radau
// IIA's Newton matrix, exactly as the system's own per-DOF damping does; declared couplings
// enter the sparse pattern.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/radau_iia.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/tensor_mass.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace {

// Viscous drag f = -c v on every DOF, with or without its df/dv.
class Drag final : public ForceModel {
 public:
  Drag(double c, bool jacobian) : c_(c), jacobian_(jacobian) {}
  const char* name() const override { return "drag"; }
  double addForce(const Eigen::VectorXd&, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override {
    f -= c_ * v;
    return 0.0;
  }
  double energy(const Eigen::VectorXd&) const override { return 0.0; }
  bool hasEnergy() const override { return false; }
  bool toleratesInversion() const override { return true; }
  bool hasStiffness() const override { return true; }  // zero
  bool hasVelocityJacobian() const override { return jacobian_; }
  void addVelocityJacobian(const Eigen::VectorXd&, const Eigen::VectorXd& v, double scale,
                           const SparsePattern& pattern, SparseMatrix& C) const override {
    for (int node = 0; node < v.size() / 3; ++node)
      pattern.addNodeBlock(C, node, node, -scale * c_ * Eigen::Matrix3d::Identity());
  }

 private:
  double c_;
  bool jacobian_;
};

// A spring between two nodes that share no element, declared as a coupling.
class LongSpring final : public ForceModel {
 public:
  LongSpring(int a, int b) : a_(a), b_(b) {}
  const char* name() const override { return "long_spring"; }
  double addForce(const Eigen::VectorXd&, const Eigen::VectorXd&, Eigen::VectorXd&) const override {
    return 0.0;
  }
  double energy(const Eigen::VectorXd&) const override { return 0.0; }
  std::vector<std::array<int, 2>> couplings() const override { return {{a_, b_}}; }

 private:
  int a_, b_;
};

std::unique_ptr<System> beam(double systemDamping) {
  Mesh mesh = cantileverBeam(0.1, 0.02, 6, 2);
  auto s = std::make_unique<System>(mesh, std::vector<Material>{Material::isotropic(5e4, 0.4, 1000.0)});
  s->models.push_back(std::make_unique<TensorMassModel>(s->mesh, s->materials));
  s->damping.setConstant(systemDamping);
  for (int n = 0; n < s->numNodes(); ++n) s->state.v.segment<3>(3 * n) = Eigen::Vector3d(0, 0, -0.5);
  s->prescribe(0.0, s->state.x, s->state.v);
  return s;
}

Eigen::VectorXd run(System& s, int frames) {
  BackwardEulerParams p;
  p.linearTolerance = 1e-13;
  BackwardEulerIntegrator be(p);
  for (int i = 0; i < frames; ++i) EXPECT_TRUE(be.advance(s, 0.02).ok);
  return s.state.x;
}

TEST(VelocityJacobian, ModelDampingIsImplicitLikeTheSystemDamping) {
  const double c = 0.02;  // per DOF, N s/m: c h / m about 0.7 for the beam's nodes
  auto reference = beam(c);
  auto implicitDrag = beam(0.0);
  implicitDrag->models.push_back(std::make_unique<Drag>(c, true));
  auto explicitDrag = beam(0.0);
  explicitDrag->models.push_back(std::make_unique<Drag>(c, false));
  ASSERT_TRUE(implicitDrag->hasVelocityJacobian());
  ASSERT_FALSE(explicitDrag->hasVelocityJacobian());
  const Eigen::VectorXd xr = run(*reference, 10);
  const Eigen::VectorXd xi = run(*implicitDrag, 10);
  const Eigen::VectorXd xe = run(*explicitDrag, 10);
  const double scale = (xr - Eigen::Map<const Eigen::VectorXd>(reference->mesh.rest.data(), xr.size()))
                           .lpNorm<Eigen::Infinity>();
  EXPECT_LT((xi - xr).lpNorm<Eigen::Infinity>(), 1e-9 * scale);
  EXPECT_GT((xe - xr).lpNorm<Eigen::Infinity>(), 1e-3 * scale)
      << "without its df/dv the drag is explicit and the answer differs";
}

struct RadauRun {
  Eigen::VectorXd x;
  StepReport total;
};

RadauRun runRadau(System& s, int frames) {
  RadauOptions o;
  o.absTol = o.relTol = 1e-8;
  RadauIIA radau(o);
  RadauRun out;
  for (int i = 0; i < frames; ++i) {
    const StepReport r = radau.advance(s, 0.02);
    EXPECT_TRUE(r.ok) << r.failure;
    out.total.substeps += r.substeps;
    out.total.newtonIterations += r.newtonIterations;
  }
  out.x = s.state.x;
  return out;
}

TEST(VelocityJacobian, RadauNewtonMatrixHoldsTheModelDampingLikeTheSystemDamping) {
  // Heavy drag (c h / m about 70 at h = 0.02 s): the velocity derivative dominates the stage
  // Jacobian, so leaving it out slows the simplified Newton iteration.
  const double c = 2.0;
  auto reference = beam(c);
  auto implicitDrag = beam(0.0);
  implicitDrag->models.push_back(std::make_unique<Drag>(c, true));
  auto explicitDrag = beam(0.0);
  explicitDrag->models.push_back(std::make_unique<Drag>(c, false));
  const RadauRun r = runRadau(*reference, 5);
  const RadauRun i = runRadau(*implicitDrag, 5);
  const RadauRun e = runRadau(*explicitDrag, 5);
  const double scale = (r.x - Eigen::Map<const Eigen::VectorXd>(reference->mesh.rest.data(),
                                                                 r.x.size()))
                           .lpNorm<Eigen::Infinity>();
  EXPECT_LT((i.x - r.x).lpNorm<Eigen::Infinity>(), 1e-9 * scale);
  EXPECT_EQ(i.total.substeps, r.total.substeps);
  // The same Jacobian; the forces are summed in another order, which may cost an iteration.
  EXPECT_NEAR(i.total.newtonIterations, r.total.newtonIterations, 0.05 * r.total.newtonIterations);
  std::printf("[ radau] drag in the Newton matrix: %d steps, %d Newton iterations; left out: "
              "%d steps, %d Newton iterations\n",
              i.total.substeps, i.total.newtonIterations, e.total.substeps,
              e.total.newtonIterations);
  EXPECT_GT(e.total.newtonIterations + 2 * e.total.substeps,
            r.total.newtonIterations + 2 * r.total.substeps)
      << "without its df/dv the Newton matrix misses the drag; steps " << e.total.substeps
      << " vs " << r.total.substeps << ", Newton iterations " << e.total.newtonIterations
      << " vs " << r.total.newtonIterations;
}

TEST(Couplings, DeclaredPairsEnterThePattern) {
  Mesh mesh = cantileverBeam(0.1, 0.02, 6, 2);
  System s(mesh, {Material::isotropic(5e4, 0.4, 1000.0)});
  const int far = s.numNodes() - 1;
  SparseMatrix before = s.pattern.zeroMatrix();
  ASSERT_EQ(before.coeff(0, 3 * far), 0.0);
  const Eigen::Index entries = before.nonZeros();
  s.models.push_back(std::make_unique<LongSpring>(0, far));
  s.addCouplingsToPattern();
  SparseMatrix after = s.pattern.zeroMatrix();
  EXPECT_EQ(after.nonZeros(), entries + 2 * 9);  // the (0, far) and (far, 0) blocks
  EXPECT_NO_THROW(s.pattern.addNodeBlock(after, 0, far, Eigen::Matrix3d::Identity()));
  EXPECT_EQ(after.coeff(2, 3 * far + 2), 1.0);
}

}  // namespace
}  // namespace tt
