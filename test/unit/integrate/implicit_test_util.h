#pragma once
// Shared by the backward-Euler preconditioner tests: a soft cantilever thrown into a large
// deflection, tight solver settings, and a force that makes the system matrix indefinite.
#include <Eigen/Core>
#include <gtest/gtest.h>
#include <memory>

#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace testutil {

// f = +k (x - x_node) at one node (a spring pushing it away from where it is asked to sit):
// with k above that node's elastic stiffness, M - h^2 K has negative eigenvalues there.
// k can be switched at run time.
class Repeller final : public ForceModel {
 public:
  Repeller(int node, Eigen::Vector3d centre, Eigen::Vector3d rest = Eigen::Vector3d::Zero())
      : node_(node), centre_(centre), rest_(rest) {}
  const char* name() const override { return "repeller"; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd&,
                  Eigen::VectorXd& f) const override {
    f.segment<3>(3 * node_) += k * (x.segment<3>(3 * node_) - centre_);
    return energy(x);
  }
  double energy(const Eigen::VectorXd& x) const override {
    return -0.5 * k * (x.segment<3>(3 * node_) - centre_).squaredNorm();
  }
  bool toleratesInversion() const override { return true; }
  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override {
    if (awayFromRestOnly && x.segment<3>(3 * node_) == rest_) return;
    pattern.addNodeBlock(K, node_, node_, scale * k * Eigen::Matrix3d::Identity());
  }
  double k = 0.0;
  // The stiffness (not the force) only where the node is away from its rest position: the
  // rest shape's matrix is then positive definite while the deformed one is not.
  bool awayFromRestOnly = false;

 private:
  int node_;
  Eigen::Vector3d centre_, rest_;
};

// A soft cantilever (StVK) thrown downwards: large deflection, so the system matrix drifts.
inline std::unique_ptr<System> beam(int cellsAlong = 8, int cellsAcross = 2) {
  Mesh mesh = cantileverBeam(0.1, 0.02, cellsAlong, cellsAcross);
  auto s = std::make_unique<System>(mesh, std::vector<Material>{Material::isotropic(5e3, 0.4, 1000.0)});
  s->models.push_back(std::make_unique<EdgeLengthModel>(s->mesh, s->materials));
  s->damping = 0.5 * s->mass;
  for (int n = 0; n < s->numNodes(); ++n) s->state.v.segment<3>(3 * n) = Eigen::Vector3d(0, 0, -1.0);
  s->prescribe(0.0, s->state.x, s->state.v);
  return s;
}

// Adds a Repeller at the system's last node (the beam's free end) ten times stiffer than the
// elastic stiffness there: M - h^2 K is indefinite at that node. Returns it (owned by s).
inline Repeller& repelTip(System& s) {
  const int tip = s.numNodes() - 1;
  auto repeller = std::make_unique<Repeller>(tip, s.state.x.segment<3>(3 * tip) + Eigen::Vector3d(0, 0, 0.01));
  Repeller& r = *repeller;
  s.models.push_back(std::move(repeller));
  SparseMatrix K;
  s.assembleStiffness(s.state.x, K);
  r.k = 10.0 * (-K.diagonal().segment<3>(3 * tip)).maxCoeff();
  return r;
}

inline BackwardEulerParams tight(BackwardEulerParams::Preconditioning preconditioner) {
  BackwardEulerParams p;
  p.linearTolerance = 1e-12;
  p.linearMaxIterations = 5000;
  p.preconditioner = preconditioner;
  p.backgroundRefactor = false;
  return p;
}

// One run of the thrown beam: where it ended and what the integrator counted.
struct RunResult {
  Eigen::VectorXd x, start;
  int linearIterations = 0;
  int slowSolves = 0;  // solves above refactorIterations or meeting non-positive curvature
  BackwardEulerDiagnostics diagnostics;
};

// The thrown beam, `cells` cells along and a quarter of them across, one solve per frame.
inline RunResult run(BackwardEulerParams p, int frames, int cells = 8) {
  auto s = beam(cells, cells / 4);
  RunResult out;
  out.start = s->state.x;
  BackwardEulerIntegrator be(p);
  for (int i = 0; i < frames; ++i) {
    const int curvatureBefore = be.diagnostics().nonPositiveCurvature;
    const StepReport r = be.advance(*s, 0.02);
    EXPECT_TRUE(r.ok) << r.failure;
    out.linearIterations += r.linearIterations;
    if (r.linearIterations > p.refactorIterations ||
        be.diagnostics().nonPositiveCurvature > curvatureBefore)
      ++out.slowSolves;
  }
  out.x = s->state.x;
  out.diagnostics = be.diagnostics();
  return out;
}

}  // namespace testutil
}  // namespace tt
