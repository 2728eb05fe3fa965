#pragma once
// Bullet's deformable bodies (Debian's libbullet-dev 3.24, the double-precision build
// libBullet*-float64) built from one of our Systems, for the benchmarks that run Bullet
// beside our models: bench_bullet_peer (beams) and bench_bullet_liver (the refined liver).
// How Bullet is configured, and why, is explained at the top of bench_bullet_peer.cpp.
// Include only in a tool that links the float64 libraries and defines
// BT_USE_DOUBLE_PRECISION (cmake/tools.cmake), never with the contact library, which links
// the single-precision Bullet under the same symbol names.
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletSoftBody/btDeformableBodySolver.h>
#include <BulletSoftBody/btDeformableGravityForce.h>
#include <BulletSoftBody/btDeformableLinearElasticityForce.h>
#include <BulletSoftBody/btDeformableMultiBodyConstraintSolver.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>
#include <BulletSoftBody/btDeformableNeoHookeanForce.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>

#include <Eigen/Core>
#include <memory>
#include <string>

#include "tissue_trainer/core/system.h"

static_assert(sizeof(btScalar) == sizeof(double), "build against Bullet's float64 libraries");

namespace tt {
namespace bullet {

// The solver with its Newton and Krylov settings reachable.
class PeerSolver : public btDeformableBodySolver {
 public:
  void configure(int newtonPasses, double newtonTolerance, int krylovIterations,
                 double krylovTolerance) {
    m_maxNewtonIterations = newtonPasses;
    m_newtonTolerance = newtonTolerance;
    m_cr.m_maxIterations = m_cg.m_maxIterations = krylovIterations;
    m_cr.setTolerance(krylovTolerance);
    m_cg.setTolerance(krylovTolerance);
  }
};

// Calls f on every node with mass of the force's bodies.
template <class F>
void forEachFreeNode(btAlignedObjectArray<btSoftBody*>& bodies, F f) {
  for (int b = 0; b < bodies.size(); ++b)
    for (int j = 0; j < bodies[b]->m_nodes.size(); ++j)
      if (bodies[b]->m_nodes[j].m_im > 0) f(bodies[b]->m_nodes[j]);
}

// Mass-proportional damping f = -c m v, implicit, and the probe that counts the solver's calls.
class MassDamping : public btDeformableLagrangianForce {
 public:
  explicit MassDamping(double rate) : rate_(rate) {}
  long residuals = 0, products = 0;

  void addScaledForces(btScalar scale, TVStack& force) override {
    ++residuals;
    addScaledDampingForce(scale, force);
  }
  void addScaledExplicitForce(btScalar, TVStack&) override {}
  void addScaledDampingForce(btScalar scale, TVStack& force) override {
    forEachFreeNode(m_softBodies, [&](const btSoftBody::Node& n) {
      force[n.index] -= scale * rate_ / n.m_im * n.m_v;
    });
  }
  void addScaledDampingForceDifferential(btScalar scale, const TVStack& dv, TVStack& df) override {
    ++products;
    forEachFreeNode(m_softBodies, [&](const btSoftBody::Node& n) {
      df[n.index] -= scale * rate_ / n.m_im * dv[n.index];
    });
  }
  void buildDampingForceDifferentialDiagonal(btScalar scale, TVStack& diagA) override {
    forEachFreeNode(m_softBodies, [&](const btSoftBody::Node& n) {
      const btScalar d = scale * rate_ / n.m_im;
      diagA[n.index] -= btVector3(d, d, d);
    });
  }
  void addScaledElasticForceDifferential(btScalar, const TVStack&, TVStack&) override {}
  void addScaledHessian(btScalar scale) override {
    forEachFreeNode(m_softBodies, [&](btSoftBody::Node& n) {
      n.m_effectiveMass += btMatrix3x3::getIdentity() * (scale * rate_ / n.m_im);
    });
  }
  // A type of its own (the world merges forces of equal type); no enumerator has special code.
  btDeformableLagrangianForceType getForceType() override {
    return static_cast<btDeformableLagrangianForceType>(7);
  }

 private:
  double rate_;
};

// A constant force per node (N, 3 per node of the body), applied as Bullet applies gravity:
// in the explicit predictor and in every residual.
class NodalForce : public btDeformableLagrangianForce {
 public:
  explicit NodalForce(const Eigen::VectorXd& force) : force_(force) {}

  void addScaledForces(btScalar scale, TVStack& force) override { addScaledExplicitForce(scale, force); }
  void addScaledExplicitForce(btScalar scale, TVStack& force) override {
    forEachFreeNode(m_softBodies, [&](const btSoftBody::Node& n) {
      const int node = static_cast<int>(n.index);  // one body: its node indices are ours
      force[n.index] += scale * btVector3(force_[3 * node], force_[3 * node + 1], force_[3 * node + 2]);
    });
  }
  void addScaledDampingForce(btScalar, TVStack&) override {}
  void addScaledDampingForceDifferential(btScalar, const TVStack&, TVStack&) override {}
  void buildDampingForceDifferentialDiagonal(btScalar, TVStack&) override {}
  void addScaledElasticForceDifferential(btScalar, const TVStack&, TVStack&) override {}
  btDeformableLagrangianForceType getForceType() override {
    return static_cast<btDeformableLagrangianForceType>(8);
  }

 private:
  Eigen::VectorXd force_;
};

struct Settings {
  std::string model;  // bullet_linear_elasticity, bullet_neohookean
  int newtonPasses = 5;
  double newtonTolerance = 1e-4;
  int krylovIterations = 300;
  double krylovTolerance = 1e-8;  // Bullet's defaults
  bool projection = true;         // Bullet's default is false (see bench_bullet_peer.cpp)
};

// What the System's scene applies beside its elastic model: gravity (m/s^2), mass damping
// -rate m v, and an optional constant nodal force (3n, N; empty: none).
struct Loads {
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  double dampingRate = 0.0;
  Eigen::VectorXd nodalForce;
};

// One deformable world holding the body of a System (its mesh, masses, constraints, state).
class Body {
 public:
  Body(const System& s, const Settings& settings, const Loads& loads)
      : dispatcher_(&collision_), world_(&dispatcher_, &broadphase_, &constraints_, &collision_, &solver_) {
    solver_.configure(settings.newtonPasses, settings.newtonTolerance, settings.krylovIterations,
                      settings.krylovTolerance);
    solver_.setImplicit(true);
    constraints_.setDeformableSolver(&solver_);
    world_.setImplicit(true);
    world_.setLineSearch(false);
    world_.setUseProjection(settings.projection);
    solver_.m_useProjection = settings.projection;
    world_.setGravity(btVector3(0, 0, 0));
    world_.getWorldInfo().m_gravity.setZero();
    world_.getWorldInfo().m_sparsesdf.Initialize();
    buildBody(s);

    const ElasticConstants& ours = s.materials.front().elasticConstants();
    const double mu = ours.mu, lambda = ours.lambda;
    if (settings.model == "bullet_linear_elasticity")
      elastic_ = std::make_unique<btDeformableLinearElasticityForce>(mu, lambda, 0.0, 0.0);
    else
      elastic_ = std::make_unique<btDeformableNeoHookeanForce>(4.0 / 3.0 * mu, lambda + 5.0 / 6.0 * mu, 0.0);
    gravity_ = std::make_unique<btDeformableGravityForce>(toBt(loads.gravity));
    damping_ = std::make_unique<MassDamping>(loads.dampingRate);
    world_.addForce(body_, elastic_.get());
    world_.addForce(body_, gravity_.get());
    world_.addForce(body_, damping_.get());
    if (loads.nodalForce.size() > 0) {
      nodal_ = std::make_unique<NodalForce>(loads.nodalForce);
      world_.addForce(body_, nodal_.get());
    }
  }
  ~Body() {
    world_.removeSoftBody(body_);
    delete body_;
  }
  Body(const Body&) = delete;
  Body& operator=(const Body&) = delete;

  // One step of h; returns the substeps Bullet took.
  int step(double h) { return world_.stepSimulation(h, 1, h); }
  void read(Eigen::VectorXd& x, Eigen::VectorXd& v) const {
    for (int n = 0; n < body_->m_nodes.size(); ++n) {
      const btSoftBody::Node& node = body_->m_nodes[n];
      for (int i = 0; i < 3; ++i) {
        x[3 * n + i] = node.m_x[i];
        v[3 * n + i] = node.m_v[i];
      }
    }
  }
  long residuals() const { return damping_->residuals; }
  long products() const { return damping_->products; }

 private:
  static btVector3 toBt(const Eigen::Vector3d& p) { return btVector3(p.x(), p.y(), p.z()); }

  // Nodes (rest shape = our mesh's, state = ours), tets, masses (constrained nodes mass 0),
  // no collision, no drag, never deactivated.
  void buildBody(const System& s) {
    btAlignedObjectArray<btVector3> nodes;
    btAlignedObjectArray<btScalar> masses;
    for (int n = 0; n < s.numNodes(); ++n) {
      nodes.push_back(toBt(s.mesh.rest.col(n)));
      masses.push_back(s.isConstrained[3 * n] ? 0.0 : s.mass[3 * n]);
    }
    body_ = new btSoftBody(&world_.getWorldInfo(), s.numNodes(), &nodes[0], &masses[0]);
    for (const Tet& t : s.mesh.tets) body_->appendTetra(t[0], t[1], t[2], t[3]);
    body_->initializeDmInverse();
    body_->m_tetraScratches.resize(body_->m_tetras.size());
    body_->m_tetraScratchesTn.resize(body_->m_tetras.size());
    body_->m_cfg.collisions = 0;
    body_->m_cfg.drag = 0;
    body_->m_cfg.m_maxStress = 0;
    body_->m_useSelfCollision = false;
    body_->setActivationState(DISABLE_DEACTIVATION);
    for (int n = 0; n < s.numNodes(); ++n) {
      btSoftBody::Node& node = body_->m_nodes[n];
      node.m_x = node.m_q = toBt(s.state.x.segment<3>(3 * n));
      node.m_v = node.m_vn = toBt(s.state.v.segment<3>(3 * n));
    }
    world_.addSoftBody(body_);
  }

  btSoftBodyRigidBodyCollisionConfiguration collision_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btDeformableMultiBodyConstraintSolver constraints_;
  PeerSolver solver_;
  btDeformableMultiBodyDynamicsWorld world_;
  btSoftBody* body_ = nullptr;
  std::unique_ptr<btDeformableLagrangianForce> elastic_, gravity_;
  std::unique_ptr<MassDamping> damping_;
  std::unique_ptr<NodalForce> nodal_;
};

}  // namespace bullet
}  // namespace tt
