#pragma once
// Landmark fitting of a quasistatic muscle system (M. Bao, "Derivation of Quasistatics and
// Landmark Optimization for Muscles", Secs. 1-3): find the parameters theta, the activations of
// the system's ActivatedForceModels (each in [0, 1]) and optionally a jaw and a cranium affine
// transform (12 numbers each), whose equilibrium x(theta) puts the landmarks at their targets,
//   minimise 1/2 |y(x(theta)) - y*|^2 (+ orthogonality terms of the jaw and cranium matrices),
// by Gauss-Newton (Sec. 1, Eq. 2: each step solves J dtheta = -r by QR), optionally damped
// (Levenberg-Marquardt rows sqrt(lambda) I under J), with the activations kept in their bounds.
//
// Jacobians at the equilibrium, K = -df/dx over the free DOFs (one factorisation per iteration):
//   activation i (Eq. 6):  K_ff dx_f/da_i = f_i(x) (free part), dx_c/da_i = 0;
//   jaw parameter p (Eq. 9 with K = -df/dx): dx_c/dp = dM_j/dp x_c0 + dt_j/dp on the jaw
//     nodes (x_c0 their positions when the fit starts) and K_ff dx_f/dp = -K_fc dx_c/dp;
//   cranium parameter q (Sec. 3.2): the cranium transform is read as a post-transform of the
//     solved rig, y^ = M_c y + t_c, so dy^/dq = dM_c/dq y + dt_c/dq exactly, and the other
//     columns are multiplied by M_c. (Read as moving constrained nodes of the solve it would be
//     exact only for rigid variations of M_c.)
#include <Eigen/Core>
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tissue_trainer/core/solve/equilibrium.h"
#include "tissue_trainer/core/system.h"

namespace tt {

class ActivatedForceModel;

// A point tied to (up to) four nodes by barycentric weights; a node landmark has weight 1 on
// its node and 0 on the others.
struct Landmark {
  std::array<int, 4> nodes{};
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // m
};

struct FitParams {
  int maxIterations = 30;
  double residualTolerance = 1e-10;  // m, RMS landmark distance
  double stepTolerance = 1e-12;      // max |dtheta| of a step
  double levenbergMarquardt = 0.0;   // lambda of the damping rows; 0: Gauss-Newton
  int maxStepHalvings = 20;          // halvings of a step that does not lower the cost
  bool fitJaw = false;
  std::vector<int> jawNodes;         // every DOF of these nodes must be constrained
  bool fitCranium = false;
  double orthogonalityWeight = 1.0;  // m, weight of the rows (M^T M - I)_ab of jaw and cranium
  EquilibriumParams equilibrium;
};

// kEquilibriumFailed: the equilibrium did not converge, or its stiffness could not be factored.
enum class FitStop { kResidual, kStep, kIterationLimit, kNoDecrease, kEquilibriumFailed };

struct FitIteration {
  double residual = 0.0;  // RMS landmark distance after the step (m)
  double step = 0.0;      // max |dtheta| of the step taken
  double cost = 0.0;      // 1/2 |r|^2 with the orthogonality rows
};

// Where the last Jacobian's wall time went (s): the stiffness assembly with the right sides,
// the one factorisation of K_ff, and the solves for its columns (one per activation and jaw
// parameter) with the landmark rows.
struct JacobianCost {
  double assembly = 0.0, factorization = 0.0, solves = 0.0;
  int columns = 0;
};

struct FitResult {
  std::vector<FitIteration> iterations;
  double initialResidual = 0.0;  // RMS landmark distance at the start (m)
  double residual = 0.0;         // at the end
  FitStop stop = FitStop::kIterationLimit;
  std::string reason;  // one line
  bool converged() const { return stop == FitStop::kResidual || stop == FitStop::kStep; }
};

class LandmarkFit {
 public:
  // The system's current activations, jaw node positions (jaw = identity) and cranium
  // (identity) are the start. Throws std::invalid_argument for a landmark node out of range,
  // no activation to fit, or a jaw node with a free DOF.
  LandmarkFit(System& system, std::vector<Landmark> landmarks, FitParams params = {});

  int activationCount() const { return static_cast<int>(activations_.size()); }
  int parameterCount() const;
  std::string parameterName(int k) const;
  // theta = (activations, jaw M row-major and t if fitted, cranium M and t if fitted).
  Eigen::VectorXd parameters() const;
  // Sets theta (activations must lie in [0, 1]) and solves the equilibrium from the last one;
  // y gets the landmark positions (3L), J (3L x P) their Jacobian when asked for. False when
  // the equilibrium did not converge or its stiffness could not be factored
  // (`failure()` says which).
  bool evaluate(const Eigen::VectorXd& theta, Eigen::VectorXd& y, Eigen::MatrixXd* J = nullptr);
  const EquilibriumReport& equilibriumReport() const { return equilibrium_; }
  const std::string& failure() const { return failure_; }
  const JacobianCost& lastJacobianCost() const { return jacobianCost_; }

  // Runs the fit from the current parameters; `onIteration` (may be empty) sees each step.
  template <class Callback>
  FitResult run(Callback onIteration);
  FitResult run();

  // Node positions of the current fit with the cranium post-transform applied (3n).
  Eigen::VectorXd fittedPositions() const;
  Eigen::Matrix3d jawMatrix() const { return jawM_; }
  Eigen::Vector3d jawTranslation() const { return jawT_; }
  Eigen::Matrix3d craniumMatrix() const { return cranM_; }
  Eigen::Vector3d craniumTranslation() const { return cranT_; }
  const std::vector<Landmark>& landmarks() const { return landmarks_; }
  const FitParams& params() const { return params_; }

 private:
  struct ActivationSlot {
    ActivatedForceModel* model;
    int index;
  };
  FitResult runImpl(const std::function<void(int, const FitIteration&)>& onIteration);
  void setParameters(const Eigen::VectorXd& theta);
  // Landmark positions of x before the cranium transform (3L).
  Eigen::VectorXd landmarkPositions(const Eigen::VectorXd& x) const;
  // Rows of the landmark Jacobian of one full-DOF column dx/dtheta_k.
  Eigen::VectorXd landmarkColumn(const Eigen::VectorXd& dx) const;
  // False when the stiffness cannot be factored.
  bool jacobian(const Eigen::VectorXd& raw, Eigen::MatrixXd& J);
  // Residual r (landmarks then orthogonality rows) and its Jacobian.
  void stackedResidual(const Eigen::VectorXd& y, const Eigen::MatrixXd* J, Eigen::VectorXd& r,
                       Eigen::MatrixXd* Jr) const;
  double rms(const Eigen::VectorXd& y) const;
  // The Gauss-Newton (or damped) step with activations at a bound and pushed out fixed.
  Eigen::VectorXd boundedStep(const Eigen::MatrixXd& J, const Eigen::VectorXd& r,
                              const Eigen::VectorXd& theta) const;
  Eigen::VectorXd projected(Eigen::VectorXd theta) const;

  System& system_;
  std::vector<Landmark> landmarks_;
  FitParams params_;
  std::vector<ActivationSlot> activations_;
  Eigen::Matrix3Xd jawRest_;  // positions of the jaw nodes at the start
  Eigen::Matrix3d jawM_ = Eigen::Matrix3d::Identity(), cranM_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d jawT_ = Eigen::Vector3d::Zero(), cranT_ = Eigen::Vector3d::Zero();
  EquilibriumSolver solver_;
  EquilibriumReport equilibrium_;
  std::string failure_;  // why the last evaluate() failed
  std::unique_ptr<CholeskyPreconditioner> jacobianFactor_;  // kept: one symbolic analysis
  JacobianCost jacobianCost_;
};

template <class Callback>
FitResult LandmarkFit::run(Callback onIteration) {
  return runImpl(onIteration);
}

// Reads a targets file: one landmark a line, `node N x y z` or `tet T b0 b1 b2 b3 x y z` (N, T
// the mesh file's numbers, mesh.numbering; barycentric weights >= 0 summing to 1 within 1e-6);
// blank lines and '#' comments are skipped. Throws InputError naming the file and line for
// anything else.
std::vector<Landmark> readLandmarks(const std::string& path, const Mesh& mesh);

const char* stopName(FitStop stop);

}  // namespace tt
