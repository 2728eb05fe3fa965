#pragma once
// Finite-difference Jacobians of a system's total force (System::computeForce: the models, the
// per-DOF damping and the external force) with respect to the positions and to the
// velocities, into matrices with the system's sparse pattern: for implicit integrators whose
// models have no analytic stiffness or velocity Jacobian.
//
// Forward differences, "Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.5.5,
// Eq. 2.149 with its sign corrected: column j of df/du is (f(u + d_j e_j) - f(u)) / d_j. The
// printed (f(u) - f(u + d_j e_j)) / d_j is -df/du, with which the implicit step of Eqs.
// 2.146-2.148 grows without bound. The perturbation is relative per DOF,
// d_j = epsilon * max(|u_j|, scale), and the step actually taken ((u_j + d_j) - u_j, exact in
// floating point) divides the difference.
//
// With colouring, DOFs whose columns share no row of the pattern are perturbed together, so
// one force evaluation gives the columns of a whole group: a greedy distance-2 colouring of
// the node graph (nodes of one colour neither share an element nor a neighbour), times the 3
// axes. Entries outside the pattern are not computed; with colouring, a force that couples
// nodes outside the pattern (a spring between nodes without a declared coupling) would be
// attributed to the wrong column, so the pattern must hold every coupling.
#include <Eigen/Core>
#include <vector>

#include "tissue_trainer/core/system.h"

namespace tt {

struct FiniteDifferenceSettings {
  double epsilon = 1.4901161193847656e-8;  // relative perturbation: sqrt of the machine epsilon
  double positionScale = 0.0;  // m; <= 0: the largest extent of the rest mesh's bounding box
  double velocityScale = 1.0;  // m/s
  bool coloring = true;        // false: one DOF per force evaluation
};

class FiniteDifferenceJacobian {
 public:
  // The groups follow the system's pattern and DOF count at construction.
  FiniteDifferenceJacobian(const System& system, FiniteDifferenceSettings settings);

  // Force evaluations per Jacobian (besides the one of f at the point itself).
  int groups() const { return static_cast<int>(groupDofs_.size()); }
  int colours() const { return colours_; }  // of the node graph; 0 without colouring
  // Built for a pattern of this size (a system whose models added couplings needs a new one).
  bool matches(const System& system) const;
  const FiniteDifferenceSettings& settings() const { return settings_; }

  // J = scale * df/dx at (x, v), given f = f(x, v); J gets the system's pattern when empty.
  void positions(const System& system, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                 const Eigen::VectorXd& f, double scale, SparseMatrix& J);
  // J = scale * df/dv at (x, v), given f = f(x, v).
  void velocities(const System& system, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  const Eigen::VectorXd& f, double scale, SparseMatrix& J);

  long forceEvaluations() const { return evaluations_; }  // since construction

 private:
  struct Entry {
    int offset, row, column;  // in the value array of the pattern
  };
  void differentiate(const System& system, bool inVelocity, const Eigen::VectorXd& x,
                     const Eigen::VectorXd& v, const Eigen::VectorXd& f, double scale,
                     SparseMatrix& J);

  FiniteDifferenceSettings settings_;
  int colours_ = 0;
  Eigen::Index dofs_ = 0;
  Eigen::Index patternNonZeros_ = 0;
  std::vector<std::vector<int>> groupDofs_;      // DOFs perturbed together
  std::vector<std::vector<Entry>> groupEntries_;  // the entries of their columns
  Eigen::VectorXd xs_, vs_, fs_, step_;
  long evaluations_ = 0;
};

// Greedy distance-2 colouring of the nodes of a pattern (nodes in index order, each the
// smallest colour none of its neighbours and their neighbours has). Returns the colour per node.
std::vector<int> distanceTwoColouring(const SparsePattern& pattern);

}  // namespace tt
