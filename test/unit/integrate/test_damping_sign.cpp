// Jeffrey, "A non-linear anisotropic Finite Element Method for surgical simulation",
// Appendix A: Picinbono's Eq A.3, m a = F + gamma v, gives the damping force the sign of the
// velocity, and Jeffrey found it unstable (v = v0 e^(gamma t) without the force). The Newtonian
// integrator integrates Eq 10, m a = F - damping v; a per-DOF damping of -gamma is therefore
// Eq A.3 as printed, and its equal-step form is then Eq A.5 as printed (checked below by
// hand). On a small clamped block released from a shear, at the same step, the printed sign
// pumps energy in while the physical sign drains it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "tissue_trainer/core/integrate/newtonian.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace {

constexpr double kRate = 6.0;  // gamma / m (1/s)

// A 2 cm block of 3 x 3 x 3 nodes, bottom fixed, sheared by `shear` along x, at rest;
// per-DOF damping sign * kRate * m.
System shearedBlock(double shear, double sign) {
  Mesh mesh = boxGrid(3, 3, 3, Eigen::Vector3d::Constant(0.02), TetSplit::kFiveMirrored);
  for (int a = 0; a < mesh.numNodes(); ++a)
    if (mesh.rest(2, a) < 1e-9) mesh.nodeTags[a] = kFixedAll;
  const std::vector<Material> materials = {Material::isotropic(2e4, 0.4, 1000.0)};
  System s(mesh, materials);
  s.models.push_back(std::make_unique<EdgeLengthModel>(s.mesh, materials));
  s.damping = sign * kRate * s.mass;
  s.updateConstraints();
  for (int a = 0; a < s.numNodes(); ++a) s.state.x[3 * a] += shear * s.mesh.rest(2, a);
  return s;
}

double totalEnergy(const System& s) {
  return s.kineticEnergy(s.state.v) + s.potentialEnergy(s.state.x);
}

bool isFreeNode(const System& s, int a) {
  return !(s.isConstrained[3 * a] && s.isConstrained[3 * a + 1] && s.isConstrained[3 * a + 2]);
}

// Negating the damping makes the equal-step form Eq A.5 as printed:
//   (m/h^2 - gamma/(2h)) x+ = F + 2m/h^2 x - (m/h^2 + gamma/(2h)) x-.
TEST(DampingSign, NegatedDampingInTheEqualStepFormIsEqA5AsPrinted) {
  System s = shearedBlock(0.05, -1.0);
  const double h = 1e-4;
  NewtonianIntegrator integrator(NewtonianParams{h, true});
  ASSERT_TRUE(integrator.advance(s, h).ok);
  const Eigen::VectorXd previous = s.state.x;
  ASSERT_TRUE(integrator.advance(s, h).ok);
  const Eigen::VectorXd current = s.state.x;
  ASSERT_TRUE(integrator.advance(s, h).ok);

  Eigen::VectorXd force(current.size());  // every force but the damping: v = 0
  s.computeForce(current, Eigen::VectorXd::Zero(current.size()), force);
  int checked = 0;
  for (int a = 0; a < s.numNodes(); ++a) {
    if (!isFreeNode(s, a)) continue;
    for (int dof = 3 * a; dof < 3 * a + 3; ++dof) {
      const double m = s.mass[dof], gamma = kRate * m;
      const double next = (force[dof] + 2.0 * m / (h * h) * current[dof] -
                           (m / (h * h) + gamma / (2.0 * h)) * previous[dof]) /
                          (m / (h * h) - gamma / (2.0 * h));
      EXPECT_NEAR(s.state.x[dof], next, 1e-12 * std::abs(next)) << "dof " << dof;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 3 * 18);  // the two upper layers of nodes
}

// Both forms (equal steps, Eq A.5; variable steps, Eq 11), the same step and 0.5 s: with the
// physical sign the energy falls to about e^(-rate t) of its start, with the printed sign it
// grows by about e^(rate t) (e^3 = 20 here).
TEST(DampingSign, PrintedSignGrowsTheEnergyWhereThePhysicalSignDecays) {
  const double h = 1e-4, duration = 0.5;
  for (bool equalSteps : {true, false}) {
    SCOPED_TRACE(equalSteps ? "equal steps (Eq A.5)" : "variable steps (Eq 11)");
    double ratio[2];
    for (int printed = 0; printed < 2; ++printed) {
      System s = shearedBlock(0.02, printed ? -1.0 : 1.0);
      const double initial = totalEnergy(s);
      ASSERT_GT(initial, 0.0);
      NewtonianIntegrator integrator(NewtonianParams{h, equalSteps});
      for (int frame = 0; frame < 50; ++frame) {
        const StepReport r = integrator.advance(s, duration / 50);
        ASSERT_TRUE(r.ok) << r.failure;
      }
      ratio[printed] = totalEnergy(s) / initial;
      std::printf("[ damping  ] %s, %s sign: energy x %.3g after %.1f s\n",
                  equalSteps ? "equal steps" : "variable steps", printed ? "printed" : "physical",
                  ratio[printed], duration);
    }
    EXPECT_LT(ratio[0], 0.2);
    EXPECT_GT(ratio[1], 5.0);
  }
}

}  // namespace
}  // namespace tt
