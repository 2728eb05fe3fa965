#pragma once
// A force model whose force is linear in a few named activations a_i in [0, 1] (M. Bao,
// "Derivation of Quasistatics and Landmark Optimization for Muscles", Sec. 1, Eq. 4):
//   f(x) = f_0(x) + sum_i a_i f_i(x),   K(x) = K_0(x) + sum_i a_i K_i(x),
// f_0 the force with every activation 0 and f_i the active force of activation i at a_i = 1,
// K = df/dx likewise. A fitting of activations to landmarks reads the parts; the simulation
// sets the activations (System::findActivation looks one up by name).
#include <string>

#include "tissue_trainer/core/model/force_model.h"

namespace tt {

class ActivatedForceModel : public ForceModel {
 public:
  virtual int activationCount() const = 0;
  virtual const std::string& activationName(int i) const = 0;
  virtual double activation(int i) const = 0;
  // Throws std::invalid_argument for a outside [0, 1]. A set value holds until the next set
  // (an activation that follows a time curve stops following it).
  virtual void setActivation(int i, double a) = 0;

  // f += f_0(x); returns the energy of f_0.
  virtual double addPassiveForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const = 0;
  // f += f_i(x); returns d(energy)/d a_i.
  virtual double addActiveForce(int i, const Eigen::VectorXd& x, Eigen::VectorXd& f) const = 0;
  // K += scale K_0(x) and K += scale K_i(x), with the system's pattern.
  virtual void addPassiveStiffness(const Eigen::VectorXd& x, double scale,
                                   const SparsePattern& pattern, SparseMatrix& K) const = 0;
  virtual void addActiveStiffness(int i, const Eigen::VectorXd& x, double scale,
                                  const SparsePattern& pattern, SparseMatrix& K) const = 0;
};

}  // namespace tt
