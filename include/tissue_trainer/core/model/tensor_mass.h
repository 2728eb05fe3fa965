#pragma once
// Jeffrey, "A non-linear anisotropic Finite Element Method for surgical simulation", Sec. 1.1
// with the anisotropic tensors of Eq 16: Cotin and Picinbono's linear tensor-mass tetrahedron.
// Per tet the tensors B_jk (3x3; B_jk = B_kj^T, not symmetric as Sec. 1.3 says) are
// precomputed as the stiffness blocks K_jk = -2 V0 B_jk; the force is f = -K_lin (x - rest)
// with K_lin the stiffness of StVK at rest, the energy 1/2 u^T K_lin u. Linear: exact for
// infinitesimal displacement, not rotation invariant (a pure 10 degree rotation gives ghost
// forces comparable to a 10% stretch).
#include <array>
#include <vector>

#include "tissue_trainer/core/model/force_model.h"
#include "tissue_trainer/core/model/material.h"
#include "tissue_trainer/core/model/stvk_kernel.h"

namespace tt {

// Eq 16 with alpha = g: B_jk = lambda/2 a_j a_k^T + mu/2 (a_k a_j^T + (a_j.a_k) I)
//                               + c (a0.a_j)(a0.a_k) a0 a0^T.
Eigen::Matrix3d tensorMassB(const StvkTet& t, int j, int k);

class TensorMassModel : public ForceModel {
 public:
  TensorMassModel(const Mesh& mesh, const std::vector<Material>& materials);

  const char* name() const override { return "tensor_mass"; }
  // Linear: the energy 1/2 u^T K u grows through flat and inverted shapes and the force
  // always points back to rest.
  bool toleratesInversion() const override { return true; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;
  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;

 private:
  // Stiffness blocks K_jk for j <= k, in the order 00 01 02 03 11 12 13 22 23 33.
  using Blocks = std::array<Eigen::Matrix3d, 10>;
  // Forces of one tet for displacements U; returns its energy.
  double tetForces(const Blocks& blocks, const Matrix34d& U, Matrix34d& fe) const;

  std::vector<Tet> tets_;
  std::vector<Blocks> blocks_;
  Eigen::VectorXd rest_;
};

}  // namespace tt
