#pragma once
// Shared by the backward-Euler preconditioner tests: a soft cantilever thrown into a large
// deflection, tight solver settings, and a force that makes the system matrix indefinite.
#include <Eigen/Core>
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

inline BackwardEulerParams tight(BackwardEulerParams::Preconditioning preconditioner) {
  BackwardEulerParams p;
  p.linearTolerance = 1e-12;
  p.linearMaxIterations = 5000;
  p.preconditioner = preconditioner;
  p.backgroundRefactor = false;
  return p;
}

}  // namespace testutil
}  // namespace tt
