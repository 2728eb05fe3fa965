#pragma once
// The 3-stage, order-5 Radau IIA implicit Runge-Kutta method with adaptive step size (Jeffrey,
// "A non-linear anisotropic Finite Element Method for surgical simulation", Appendix D; Hairer
// & Wanner, Solving ODEs II, IV.8). The second-order system
// p' = v, v' = M^-1 f(p, v) is integrated as the first-order system y' = F(y), y = (p, v).
// Each step solves the stage equations by simplified Newton iterations, transformed with the
// eigen-decomposition of A^-1 into one real and one complex linear system (D.15-D.17). Both
// are reduced to 3n x 3n systems in the position increment:
//   (sigma^2 M - sigma D - K) dp = M r_v + (sigma M - D) r_p,   dv = sigma dp - r_p,
// with K = df/dp, D = df/dv, sigma = gamma/h (real) or (alpha + i beta)/h (complex).
// Constrained DOFs follow System::prescribe at every stage and are not unknowns.
#include <Eigen/Core>
#include <memory>

#include "tissue_trainer/core/integrate/stepped_integrator.h"

namespace tt {

// The Butcher tableau, its transformation to block-diagonal form and the derived constants.
struct RadauTableau {
  Eigen::Matrix3d A, Ainv;
  Eigen::Vector3d b, c;
  // T^-1 A^-1 T = [[gamma, 0, 0], [0, alpha, -beta], [0, beta, alpha]], beta > 0.
  Eigen::Matrix3d T, Tinv;
  double gamma = 0.0, alpha = 0.0, beta = 0.0;
  // Error estimate: y_hat - y = (h / gamma) F(y0) + sum_i errorWeights[i] z_i (D.22), from the
  // order-3 embedded method with b_hat_0 = 1 / gamma.
  Eigen::Vector3d errorWeights;

  static const RadauTableau& get();

  // Starting values of the next step from the stages z_j of the last accepted step:
  // z_i^0 = sum_j P(i, j) z_j, the collocation polynomial through (0, 0), (c_j, z_j)
  // evaluated at 1 + ratio c_i, minus z_3; ratio = h_new / h_old (D.19, D.23-D.26).
  Eigen::Matrix3d extrapolation(double ratio) const;
};

enum class RadauJacobian {
  kSimplified,  // force derivatives omitted: J = [[0, I], [0, -M^-1 C]]
  kNumerical,   // finite differences of the force in positions and velocities
  kAnalytical,  // System::assembleStiffness, and df/dv = -diag(c) plus the models' velocity
                // Jacobians (System::assembleVelocityJacobian)
};

struct RadauOptions {
  RadauJacobian jacobian = RadauJacobian::kAnalytical;
  double absTol = 1e-6;          // positions (m)
  double absTolVelocity = -1.0;  // velocities (m/s); <= 0: same as absTol
  double relTol = 1e-6;
  bool adaptive = true;      // false: fixed steps of initialStep (frame split evenly)
  double initialStep = 1e-3; // s
  double maxStep = 1e30;     // s
  double minStep = 1e-14;    // s; smaller steps fail the frame
  int maxNewtonIterations = 7;
  // > 0: the Newton iteration stops when its predicted remaining error (weighted norm) is
  // below this; <= 0 (default): Hairer and Wanner's max(10 eps / rtol, min(0.03, sqrt(rtol)))
  // with their internal rtol, which their RADAU5 code uses.
  double newtonTolerance = 0.0;
  int maxStepsPerFrame = 100000;  // step attempts
  // The step-size controller (ErrorStepControl, step_control.h):
  double safety = 0.9;       // step size safety factor
  double maxGrowth = 8.0;    // h_new <= maxGrowth * h
  double maxShrink = 5.0;    // h_new >= h / maxShrink
};

// Totals since construction (or resetStatistics), beyond what StepReport carries.
struct RadauStatistics {
  long forceEvaluations = 0;
  long factorizations = 0;  // sparse LU factorizations (each counts the real and complex pair)
  long linearSolves = 0;
};

class RadauIIA : public SteppedIntegrator {
 public:
  explicit RadauIIA(RadauOptions options = {});
  ~RadauIIA() override;

  const char* name() const override { return "radau_iia"; }
  bool needsStiffness() const override { return options_.jacobian == RadauJacobian::kAnalytical; }

  // advance() integrates over frameTime. The report's errorEstimate is the largest weighted
  // RMS norm of the local error estimate over the accepted substeps (1 = exactly at
  // tolerance); linearIterations counts linear solves (each a real or complex 3n x 3n LU
  // solve); rejected counts steps rejected by the error test and by Newton failure.

  const RadauOptions& options() const { return options_; }
  const RadauStatistics& statistics() const { return statistics_; }
  void resetStatistics() { statistics_ = {}; }
  // Forget the step size and stage history (the next frame starts from initialStep) and the
  // matrices built for the last system; call it after changing the system's pattern.
  void reset();

 private:
  struct Workspace;
  FrameStart beginFrame(System& system, double frameTime) override;
  StepAttempt attempt(System& system, const StepContext& step, StepReport& report) override;
  std::string accept(System& system, const StepContext& step) override;
  void endFrame(System& system) override;
  void abandonFrame(const System&) override;

  RadauOptions options_;
  RadauStatistics statistics_;
  std::unique_ptr<Workspace> work_;
};

}  // namespace tt
