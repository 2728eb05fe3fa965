#pragma once
// Jeffrey, "A non-linear anisotropic Finite Element Method for surgical simulation",
// Secs. 1.2-1.3: Picinbono's displacement-based non-linear, transversely isotropic tetrahedron
// (Eq 13 with the anisotropic tensors B, C, D of Eqs 16-18), evaluated from the nodal
// displacements U = x - rest as sums over node indices, as the paper does.
//   AlphaSign::kCorrect      : alpha_j = +g_j (the printed Eq 5 has the wrong sign). Then
//                              Eq 13 is the StVK force polynomial itself; digits are lost only
//                              under large rigid translation, because it works with
//                              displacements.
//   AlphaSign::kPaperLiteral : alpha_j = -g_j, Eq 5 as printed. Eq 13 then gives the StVK force
//                              of the point-reflected displacement: f(x) = -f_StVK(2 rest - x),
//                              energy E_StVK(2 rest - x), stiffness K_StVK(2 rest - x). Kept to
//                              reproduce the paper's printed sign, not for simulation.
// Energy: the density is the sum of homogeneous parts of degrees 2, 3, 4 in U, so
// psi = U:F2/2 + U:F3/3 + U:F4/4 (Euler) with F_k the parts of Eq 13.
#include <string>
#include <vector>

#include "tissue_trainer/core/model/force_model.h"
#include "tissue_trainer/core/model/material.h"
#include "tissue_trainer/core/model/stvk_kernel.h"

namespace tt {

enum class AlphaSign { kCorrect, kPaperLiteral };

// "correct" or "paper_literal"; returns false for anything else.
bool parseAlphaSign(const std::string& name, AlphaSign& sign);

// Eq 13 for one tet: G (columns p) = the positive gradient of the density w.r.t. x_p, given
// displacements U and the tet's constants with alpha = sign * g. Returns the density.
double picinbonoTetGradient(const Matrix34d& U, const StvkTet& t, double alphaSign, Matrix34d& G);

class StvkDisplacementModel : public ForceModel {
 public:
  StvkDisplacementModel(const Mesh& mesh, const std::vector<Material>& materials,
                        AlphaSign sign = AlphaSign::kCorrect);

  const char* name() const override { return "stvk_displacement"; }
  // The same St Venant-Kirchhoff polynomial as edge_length: not for inverted tets.
  bool toleratesInversion() const override { return false; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;
  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;

  AlphaSign alphaSign() const { return sign_; }

 private:
  double signValue() const { return sign_ == AlphaSign::kCorrect ? 1.0 : -1.0; }

  std::vector<Tet> tets_;
  std::vector<StvkTet> stvk_;
  Eigen::VectorXd rest_;
  AlphaSign sign_;
};

}  // namespace tt
