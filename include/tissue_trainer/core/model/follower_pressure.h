#pragma once
// A pressure p on a set of boundary triangles that follows the deformed surface: on the
// current triangle (x_a, x_b, x_c) with area vector a = (x_b - x_a) x (x_c - x_a) / 2 (its
// length the area, its direction the outward normal of the mesh's surface), each of the three
// nodes gets
//   f = -p a / 3,
// the exact consistent load of a uniform pressure on a linear triangle; p > 0 pushes into the
// body (the load of Problem 1 of Land et al., "Verification of cardiac mechanics software:
// benchmark problems and solutions for testing active and passive material behaviour", 2015).
//
// Stiffness: da / dx_a = [x_c - x_b]x / 2, da / dx_b = [x_a - x_c]x / 2,
// da / dx_c = [x_b - x_a]x / 2 ([v]x w = v x w), so df_i / dx_j = -p/3 da / dx_j for every i:
// skew blocks, not symmetric in general. On a closed surface (or one whose boundary is held)
// the assembled matrix is symmetric, the load being then -d(p V)/dx; on an open surface with
// a free boundary (the beam's bottom face) it is not, and no potential exists.
//
// The quasistatic solve takes the stiffness into conjugate gradients, which need a symmetric
// matrix: addStiffness and addStiffnessTimes give the symmetric part (K + K^T) / 2 of each
// triangle's block (exact where the assembled matrix is symmetric). Newton on it converges
// linearly rather than quadratically when the skew part at the free edges matters; the exact
// matrix is addExactStiffness (its finite-difference test is test_follower_pressure.cpp).
// The model has no energy; the quasistatic line search holds its load at each Newton
// iteration's start (isFollowerLoad, solve/equilibrium.h).
#include <array>
#include <vector>

#include "tissue_trainer/core/model/force_model.h"
#include "tissue_trainer/core/model/time_curve.h"

namespace tt {

class FollowerPressureModel final : public ForceModel {
 public:
  using Face = std::array<int, 3>;  // nodes, right-handed about the outward normal

  // p in Pa; with a curve, beginStep sets p = curve(t) (the quasistatic solve ramps the load
  // by it, one frame per load step).
  FollowerPressureModel(std::vector<Face> faces, double pressure);
  FollowerPressureModel(std::vector<Face> faces, const TimeCurve& pressure);

  const char* name() const override { return "follower_pressure"; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd&) const override { return 0.0; }
  bool hasEnergy() const override { return false; }
  bool isFollowerLoad() const override { return true; }
  bool toleratesInversion() const override { return true; }  // no elements of its own
  bool needsStepUpdates() const override { return followsCurve_; }
  void beginStep(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& v) override;

  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;
  bool hasStiffnessProduct() const override { return true; }
  void addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double scale,
                         Eigen::VectorXd& out) const override;
  // K += scale * df/dx exactly (not symmetric in general).
  void addExactStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                         SparseMatrix& K) const;

  // d f_i / d x_j of one face's three nodes (row block i, column block j).
  static Eigen::Matrix<double, 9, 9> faceJacobian(const Eigen::VectorXd& x, const Face& face,
                                                  double pressure);
  // The pressure of the current step (Pa).
  double pressure() const { return pressure_; }
  const std::vector<Face>& faces() const { return faces_; }

 private:
  void addStiffnessBlocks(const Eigen::VectorXd& x, double scale, bool symmetric,
                          const SparsePattern& pattern, SparseMatrix& K) const;

  std::vector<Face> faces_;
  double pressure_ = 0.0;
  bool followsCurve_ = false;
  TimeCurve curve_;
};

}  // namespace tt
