#pragma once
// The force model `muscle_groups`: the teran_muscle law (material/teran_muscle.h) on every
// element of the mesh, with named muscle groups, each a set of elements with its own fibre
// field and its own activation (M. Bao, "Derivation of Quasistatics and Landmark Optimization
// for Muscles", Sec. 1, Eq. 4 and Sec. 4.3, Eq. 10). The law's energy is linear in alpha: its
// active term is sigma_max alpha Phi_a(lam) and nothing else depends on alpha, so
//   f = f_0 + sum_i a_i f_i,
// f_0 the law at alpha = 0 on every element (elements outside every group are passive muscle
// tissue along their own fibre frame) and f_i the force of d psi / d alpha = sigma_max
// Phi_a(lam) on the elements of group i. Each part is its own element model over the whole mesh
// (in part i the elements outside group i carry a zero law, so that the element numbering is
// the one the system's sparse pattern places stiffness blocks by): f_i is evaluated from the
// active term alone, never as a difference of two forces. The total force, energy and
// stiffness are evaluated in one pass over the mesh by a third element model whose elements
// carry their group's activation (the law at alpha = a_i, equal to f_0 + a_i f_i to
// round-off), kept up to date when an activation changes. With inversion handling all parts
// are taken at the same clamped F, where the law is still linear in alpha; with PSD
// projection each part is projected on its own (their sum is then PSD too, but it is not the
// projection of the sum), so the total stiffness is then the sum of the parts' (one pass
// per group with a nonzero activation).
#include <memory>
#include <string>
#include <vector>

#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/model/time_curve.h"

namespace tt {

struct MuscleGroup {
  std::string name;
  std::vector<int> elements;  // tets first, then hexes; sorted, each once
  double activation = 0.0;    // in [0, 1]
  bool followsCurve = false;  // true: the activation is curve(t) at every step's start
  TimeCurve curve;
};

class MuscleGroupsModel final : public ActivatedForceModel {
 public:
  using Constants = TeranMuscleLaw::Constants;

  // `mesh` carries the groups' fibre frames; `constants` per material id (their activations
  // are ignored). Throws std::invalid_argument for an empty or repeated name, a group without
  // elements, an element in two groups or outside the mesh, an activation outside [0, 1], or
  // an element inverted or flat at rest.
  MuscleGroupsModel(const Mesh& mesh, const std::vector<Constants>& constants,
                    std::vector<MuscleGroup> groups, const LawOptions& options);

  const char* name() const override { return "muscle_groups"; }
  bool toleratesInversion() const override { return passive_.toleratesInversion(); }

  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;

  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;
  bool hasStiffnessProduct() const override { return true; }
  void addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double scale,
                         Eigen::VectorXd& out) const override;

  bool needsStepUpdates() const override;
  void beginStep(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& v) override;

  int activationCount() const override { return static_cast<int>(groups_.size()); }
  const std::string& activationName(int i) const override { return groups_.at(i).name; }
  double activation(int i) const override { return groups_.at(i).activation; }
  void setActivation(int i, double a) override;
  // The index of the group called `name`, or -1.
  int groupIndex(const std::string& name) const;
  const MuscleGroup& group(int i) const { return groups_.at(i); }

  double addPassiveForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const override;
  double addActiveForce(int i, const Eigen::VectorXd& x, Eigen::VectorXd& f) const override;
  void addPassiveStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                           SparseMatrix& K) const override;
  void addActiveStiffness(int i, const Eigen::VectorXd& x, double scale,
                          const SparsePattern& pattern, SparseMatrix& K) const override;

 private:
  using Model = HyperelasticModel<TeranMuscleLaw>;

  // Writes group i's activation into the elements of total_.
  void applyActivation(int i);

  std::vector<MuscleGroup> groups_;
  Model passive_;
  Model total_;  // every element at its group's activation
  std::vector<std::unique_ptr<Model>> active_;  // one per group, over its elements only
};

}  // namespace tt
