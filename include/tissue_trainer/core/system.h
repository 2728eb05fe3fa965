#pragma once
// A System is what a scene builds: the mesh, lumped masses, per-DOF damping, the listed force
// models, the constraints (fixed and controlled DOFs) and the current state. Nothing the
// scene does not list is constructed, so nothing unlisted is evaluated.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/model/force_model.h"
#include "tissue_trainer/core/model/material.h"
#include "tissue_trainer/core/solve/sparse_pattern.h"

namespace tt {

class ActivatedForceModel;

// One activation of a model (a muscle of `muscle_groups`): model->setActivation(index, a).
struct ActivationRef {
  ActivatedForceModel* model = nullptr;  // nullptr: no activation of that name
  int index = -1;
};

struct State {
  Eigen::VectorXd x;  // positions, 3n (m)
  Eigen::VectorXd v;  // velocities, 3n (m/s)
  double t = 0.0;     // s
};

// Piecewise-linear displacement from the rest position over time (held after the last key),
// plus a constant velocity from t = 0 on: offset(t) = path(t) + velocity t.
struct PrescribedPath {
  std::vector<double> times;               // strictly increasing, s
  std::vector<Eigen::Vector3d> offsets;    // displacement at each time, m
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // m/s
  Eigen::Vector3d offsetAt(double t) const;
  Eigen::Vector3d velocityAt(double t) const;
};

// Nodes whose controlled axes follow the path ("Adamss: Advanced Anisotropic Mass-Spring
// System", Sec. 2.6: control tags per axis); their other axes stay free (or fixed by tags).
struct ControlledSet {
  std::vector<int> nodes;
  PrescribedPath path;
  std::uint8_t axes = kFixedAll;  // kFixedX | kFixedY | kFixedZ bits: the controlled axes
};

class System {
 public:
  System() = default;
  // Builds the sparsity pattern (tets and hexes) and lumped masses ("Adamss: Advanced Anisotropic
  // Mass-Spring System", Sec. 2.3.1.1, Eq. 2.3, m_i = sum_k rho_k V_k / N_k: each
  // node gets rho * V0 / 4 of every tet and rho * V0 / 8 of every hex it belongs to), state at
  // rest, no models, no damping. Tets and hexes are both elements (a mixed mesh has both; the
  // box generator gives one or the other, never a hex and its own tet split).
  System(Mesh mesh, std::vector<Material> materials);

  int numNodes() const { return mesh.numNodes(); }
  int numDofs() const { return 3 * mesh.numNodes(); }

  // Total force at (x, v): every model, the damping -c .* v and the external force.
  // Returns the potential energy of the models. Constrained DOFs are left as computed.
  double computeForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                      Eigen::VectorXd& f) const;
  double potentialEnergy(const Eigen::VectorXd& x) const;
  double kineticEnergy(const Eigen::VectorXd& v) const;

  // Tells the models that need it (ForceModel::needsStepUpdates) that a step starts at time t
  // from the current state.
  void beginStep(double t);

  // Rebuilds the pattern with the node pairs the models declare (ForceModel::couplings);
  // call after adding models that declare any.
  void addCouplingsToPattern();

  // True when every model provides an analytic stiffness (implicit integrators need it).
  bool hasStiffness() const;
  // K = scale * sum of the models' df/dx at x, with the system pattern (K is resized if
  // empty): with scale = -h^2 an implicit step assembles its matrix in place. projected: each
  // model's positive semi-definite approximation where it has one (addProjectedStiffness).
  void assembleStiffness(const Eigen::VectorXd& x, SparseMatrix& K, double scale = 1.0,
                         bool projected = false) const;
  bool hasProjectedStiffness() const;  // a model has a projection of its own

  // True when a model has velocity-dependent forces with an assembled df/dv.
  bool hasVelocityJacobian() const;
  // C = sum of the models' df/dv at (x, v), with the system pattern (C is resized if empty).
  // The per-DOF `damping` is not in it (implicit integrators add it on the diagonal).
  void assembleVelocityJacobian(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                                SparseMatrix& C) const;

  // The activation called `name` among the models' (ActivatedForceModel), e.g. a muscle of
  // `muscle_groups`, for setting it at run time; {nullptr, -1} when there is none.
  ActivationRef findActivation(const std::string& name) const;

  // Writes the prescribed positions and velocities of constrained DOFs at time t.
  void prescribe(double t, Eigen::VectorXd& x, Eigen::VectorXd& v) const;
  // Sets the entries of constrained DOFs to zero.
  void zeroConstrained(Eigen::VectorXd& r) const;
  // Makes constrained rows and columns of A identity rows/columns (A keeps its pattern).
  void constrainMatrix(SparseMatrix& A) const;

  // Marks the DOFs of fixed tags and of controlled sets; call after changing either.
  void updateConstraints();

  Mesh mesh;
  std::vector<Material> materials;   // indexed by mesh.material
  Eigen::VectorXd mass;              // lumped, per DOF (kg)
  Eigen::VectorXd damping;           // per DOF, f_damp = -damping .* v (N s/m)
  Eigen::VectorXd externalForce;     // per DOF (N), e.g. contact
  std::vector<std::unique_ptr<ForceModel>> models;
  std::vector<ControlledSet> controlled;
  std::vector<int> constrainedDofs;  // sorted DOF indices with prescribed position
  std::vector<std::uint8_t> isConstrained;  // per DOF
  SparsePattern pattern;
  State state;
};

}  // namespace tt
