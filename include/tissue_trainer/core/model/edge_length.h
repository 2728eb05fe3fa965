#pragma once
// Jeffrey, "A non-linear anisotropic Finite Element Method for surgical simulation", Sec. 2:
// the translation-invariant, transversely isotropic St Venant-Kirchhoff tetrahedron written
// with edge lengths (Eqs 29 and 31; Eq 24's lambda^T, mu^T read as lambda^L, mu^L, and V, A_j,
// K_jk taken at rest).
// Three evaluation paths of the same polynomial:
//   kFast    : F, E, S (stvk_kernel.h), the cheapest way to evaluate it;
//   kLiteral : the packed single-sum force of Eq 31 and the energy of Eqs 28-29, from rest
//              K_jk (Eq 20), face areas A_j, alpha_j = g_j and the deformed squared edge lengths;
//   kEq30    : the unpacked force of Eq 30 (sums over the 3 edges j-p at node p and the 3
//              edges j-k opposite it; line 4's K_jkm read as K_jkmp, Eq 21), with the literal
//              path's constants and energy. The paper finds Eq 31 about 35 % faster
//              (bench_forces measures both).
// All give energy V0 W and physical force -V0 F_p (the printed W is an energy density and
// the printed F_p its positive gradient) and share the analytic stiffness.
#include <array>
#include <string>
#include <vector>

#include "tissue_trainer/core/model/force_model.h"
#include "tissue_trainer/core/model/material.h"
#include "tissue_trainer/core/model/stvk_kernel.h"

namespace tt {

enum class EdgeLengthPath { kFast, kLiteral, kEq30 };

// "fast", "literal" or "eq30"; returns false for anything else.
bool parseEdgeLengthPath(const std::string& name, EdgeLengthPath& path);

// Rest constants of one tet for the literal and Eq 30 paths (edges ordered 01 02 03 12 13 23).
struct EdgeLengthLiteralTet {
  std::array<double, 6> restSq;   // l_jk^2
  std::array<double, 6> K;        // K_jk, Eq 20
  std::array<double, 4> areaSq;   // A_j^2, face opposite node j
  std::array<double, 4> fibreGrad;  // a0 . alpha_j
  double volume = 0.0;
  double muScale = 0.0;      // mu / (162 V^4)
  double lambdaMuScale = 0.0;  // (lambda + mu) / (162 V^4)
  double c = 0.0;            // (lambdaL - lambda)/2 + (muL - mu)
};

EdgeLengthLiteralTet makeEdgeLengthLiteralTet(const Eigen::Matrix3Xd& rest, const Tet& tet,
                                              const Eigen::Vector3d& fibre, const Material& m);
// Eq 31 (positive gradient of the density W w.r.t. the deformed positions, columns p).
Matrix34d edgeLengthLiteralGradient(const Matrix34d& xe, const EdgeLengthLiteralTet& t);
// Eq 30, the same gradient unpacked into two sums.
Matrix34d edgeLengthEq30Gradient(const Matrix34d& xe, const EdgeLengthLiteralTet& t);
// Eqs 28-29: the density W.
double edgeLengthLiteralDensity(const Matrix34d& xe, const EdgeLengthLiteralTet& t);

class EdgeLengthModel : public ForceModel {
 public:
  // psdProjection: the stiffness for the system matrix made positive semi-definite
  // (addStvkTetStiffness); the forces and energy are unchanged.
  EdgeLengthModel(const Mesh& mesh, const std::vector<Material>& materials,
                  EdgeLengthPath path = EdgeLengthPath::kFast, bool psdProjection = false);

  const char* name() const override { return "edge_length"; }
  // St Venant-Kirchhoff (it depends on the edge lengths, i.e. on F^T F, only): a mirrored
  // tet has zero energy and force, a flat one no restoring force against the collapse.
  bool toleratesInversion() const override { return false; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;
  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;
  bool hasProjectedStiffness() const override { return true; }
  void addProjectedStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                             SparseMatrix& K) const override;

  EdgeLengthPath path() const { return path_; }
  bool psdProjection() const { return psdProjection_; }

 private:
  std::vector<Tet> tets_;
  std::vector<StvkTet> stvk_;
  std::vector<EdgeLengthLiteralTet> literal_;  // filled only for the literal and Eq 30 paths
  EdgeLengthPath path_;
  bool psdProjection_ = false;
};

}  // namespace tt
