#pragma once
// The muscle forces split by activation, for fitting activations to landmarks (M. Bao,
// "Derivation of Quasistatics and Landmark Optimization for Muscles", Sec. 1, Eq. 4): the
// energy of teran_muscle is linear in alpha, so for muscles m (here: the mesh's material ids,
// each with its own activation)
//   f(x, alpha) = f_0(x) + sum_m alpha_m f_m(x),
// f_0 the force with every activation 0 and f_m the force of muscle m's active fibre term at
// alpha_m = 1. f_m is evaluated from that term alone (not as a difference of two forces), so it
// carries no round-off of the passive part. With inversion handling both are evaluated at the
// clamped F, where the law is still linear in alpha.
#include <Eigen/Core>
#include <vector>

#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/model/hyperelastic.h"

namespace tt {

class MuscleActivationForces {
 public:
  using Constants = TeranMuscleLaw::Constants;

  // `constants` per material id; their activations are ignored.
  MuscleActivationForces(const Mesh& mesh, std::vector<Constants> constants,
                         const LawOptions& options)
      : passive_(mesh, withActivation(constants, 0.0), options) {
    active_.reserve(constants.size());
    for (std::size_t m = 0; m < constants.size(); ++m)
      active_.emplace_back(muscleElements(mesh, static_cast<int>(m)),
                           std::vector<Constants>{TeranMuscleLaw::activationTerm(constants[m])},
                           options);
  }

  int numMuscles() const { return static_cast<int>(active_.size()); }

  // f_0 at x.
  Eigen::VectorXd passiveForce(const Eigen::VectorXd& x) const { return force(passive_, x); }
  // f_m at x.
  Eigen::VectorXd activationForce(int m, const Eigen::VectorXd& x) const {
    return force(active_.at(m), x);
  }
  // f_0 + sum_m alpha_m f_m.
  Eigen::VectorXd totalForce(const Eigen::VectorXd& x, const std::vector<double>& alpha) const {
    Eigen::VectorXd f = passiveForce(x);
    for (int m = 0; m < numMuscles(); ++m)
      if (alpha.at(m) != 0.0) f += alpha[m] * activationForce(m, x);
    return f;
  }

 private:
  using Model = HyperelasticModel<TeranMuscleLaw>;

  static std::vector<Constants> withActivation(std::vector<Constants> k, double alpha) {
    for (Constants& c : k) c.activation = alpha;
    return k;
  }
  // The elements of material m on all nodes, all with material id 0.
  static Mesh muscleElements(const Mesh& mesh, int m) {
    Mesh out;
    out.rest = mesh.rest;
    for (std::size_t e = 0; e < mesh.tets.size(); ++e)
      if (mesh.material[e] == m) out.tets.push_back(mesh.tets[e]), out.fibreFrame.push_back(mesh.fibreFrame[e]);
    for (std::size_t e = 0; e < mesh.hexes.size(); ++e)
      if (mesh.hexMaterial[e] == m)
        out.hexes.push_back(mesh.hexes[e]), out.hexFibreFrame.push_back(mesh.hexFibreFrame[e]);
    out.material.assign(out.tets.size(), 0);
    out.hexMaterial.assign(out.hexes.size(), 0);
    out.nodeTags = mesh.nodeTags;
    return out;
  }
  static Eigen::VectorXd force(const Model& model, const Eigen::VectorXd& x) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
    model.addForce(x, Eigen::VectorXd::Zero(x.size()), f);
    return f;
  }

  Model passive_;
  std::vector<Model> active_;
};

}  // namespace tt
