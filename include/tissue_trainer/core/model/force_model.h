#pragma once
// The interface every force model implements. A model holds its per-element constants
// (precomputed at construction) and evaluates forces, energy and stiffness for a state.
// Virtual calls happen once per model per evaluation, never per element.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "tissue_trainer/core/solve/sparse_pattern.h"

namespace tt {

class ForceModel {
 public:
  virtual ~ForceModel() = default;

  virtual const char* name() const = 0;

  // Adds the physical force (N, minus the energy gradient for conservative models) at
  // positions x and velocities v (both 3n) into f. Returns the potential energy in J
  // (0 for models without one).
  virtual double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                          Eigen::VectorXd& f) const = 0;

  // Potential energy in J at x (0 where the model has none).
  virtual double energy(const Eigen::VectorXd& x) const = 0;
  virtual bool hasEnergy() const { return true; }
  // True for a load without a potential whose force follows the deformation (a follower
  // pressure, hasEnergy() false): the quasistatic equilibrium's line search then judges steps
  // by the other models' energy minus the work of this load held at the force it has at the
  // Newton iteration's start (solve/equilibrium.h), rather than by the residual alone.
  virtual bool isFollowerLoad() const { return false; }
  // True for body loads such as gravity, whose energy is not elastic (logs report it apart).
  virtual bool isBodyLoad() const { return false; }
  // True when inverted or flat elements are states the model handles: its energy keeps
  // rising through them and its force pushes back toward the rest shape (or it has no
  // elements). False (the default, so a new model is checked until it says otherwise) when
  // they are not: the stability guard then rejects steps that invert or flatten a tet.
  virtual bool toleratesInversion() const { return false; }
  // Quantities the model reports at every frame beside its energy, e.g. the enclosed volume of
  // a cavity (m^3): the scene's CSV log gives each a column NAME_K (K counting the models that
  // report NAME). Most models report none.
  virtual int observableCount() const { return 0; }
  virtual const char* observableName(int /*k*/) const { return ""; }
  virtual double observable(int /*k*/, const Eigen::VectorXd& /*x*/) const { return 0.0; }

  // K += scale * df/dx at x, into a matrix with the system's pattern.
  virtual bool hasStiffness() const { return false; }
  virtual void addStiffness(const Eigen::VectorXd& /*x*/, double /*scale*/,
                            const SparsePattern& /*pattern*/, SparseMatrix& /*K*/) const {}

  // As addStiffness, with the energy Hessian -df/dx replaced by a positive semi-definite
  // approximation: what a preconditioner's factor is made from where the exact matrix is
  // indefinite (BackwardEulerIntegrator). Models that answer true implement it; the default is
  // the stiffness itself.
  virtual bool hasProjectedStiffness() const { return false; }
  virtual void addProjectedStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                                     SparseMatrix& K) const {
    addStiffness(x, scale, pattern, K);
  }

  // out += scale * (df/dx at x) d without assembling K (matrix-free solvers, the
  // stiffness-times-vector output of tissue_cli). Models that answer true implement it.
  virtual bool hasStiffnessProduct() const { return false; }
  virtual void addStiffnessTimes(const Eigen::VectorXd& /*x*/, const Eigen::VectorXd& /*d*/,
                                 double /*scale*/, Eigen::VectorXd& /*out*/) const {}

  // C += scale * df/dv at (x, v), into a matrix with the system's pattern: velocity-dependent
  // forces (damping, friction) that implicit integrators treat implicitly.
  virtual bool hasVelocityJacobian() const { return false; }
  virtual void addVelocityJacobian(const Eigen::VectorXd& /*x*/, const Eigen::VectorXd& /*v*/,
                                   double /*scale*/, const SparsePattern& /*pattern*/,
                                   SparseMatrix& /*C*/) const {}

  // Models whose forces change with time or adapt between steps (a time curve of active
  // tension, a cavity pressure, an adaptive spring) answer true; the frame loop then calls
  // beginStep once before every step attempt with the positions and velocities at the step's
  // start and the time of the step's forces (its start; its end for the quasistatic solve).
  // A rejected step is attempted again from the same start, so beginStep must give the same
  // result when called twice with it.
  virtual bool needsStepUpdates() const { return false; }
  virtual void beginStep(double /*t*/, const Eigen::VectorXd& /*x*/,
                         const Eigen::VectorXd& /*v*/) {}

  // Node pairs this model couples beyond the mesh's elements (springs between arbitrary
  // nodes); the system's sparse pattern is built to include them.
  virtual std::vector<std::array<int, 2>> couplings() const { return {}; }
};

}  // namespace tt
