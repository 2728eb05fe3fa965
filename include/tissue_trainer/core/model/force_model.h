#pragma once
// The interface every force model implements. A model holds its per-element constants
// (precomputed at construction) and evaluates forces, energy and stiffness for a state.
// Virtual calls happen once per model per evaluation, never per element.
#include <Eigen/Core>

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
  // True for body loads such as gravity, whose energy is not elastic (logs report it apart).
  virtual bool isBodyLoad() const { return false; }
  // True when inverted or flat elements are states the model handles: its energy keeps
  // rising through them and its force pushes back toward the rest shape (or it has no
  // elements). False (the default, so a new model is checked until it says otherwise) when
  // they are not: the stability guard then rejects steps that invert or flatten a tet.
  virtual bool toleratesInversion() const { return false; }

  // K += scale * df/dx at x, into a matrix with the system's pattern.
  virtual bool hasStiffness() const { return false; }
  virtual void addStiffness(const Eigen::VectorXd& /*x*/, double /*scale*/,
                            const SparsePattern& /*pattern*/, SparseMatrix& /*K*/) const {}
};

}  // namespace tt
