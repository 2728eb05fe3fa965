#pragma once
// Inverse kinematics of the tip position: damped least squares within the joint limits
// (an active set drops the variables a limit holds), with a step that never increases the
// distance. Never returns NaN: a non-finite target or seed leaves the (clamped) seed.
// An unreachable target gives the closest pose found and says so.
#include <Eigen/Core>
#include <vector>

#include "tissue_trainer/core/kinematics/chain.h"

namespace tt::kin {

struct IkOptions {
  std::vector<int> variables;   // the variables IK may move; empty: all of them
  int maxIterations = 50;
  double tolerance = 1e-6;      // m: a target nearer than this counts as reached
  double damping = 1e-3;        // m: lambda of J^T (J J^T + lambda^2 I)^-1
};

enum class IkStatus { kReached, kUnreachable, kInvalidInput };

struct IkResult {
  Eigen::VectorXd q;            // always finite and within the limits
  double error = 0.0;           // m, distance tip - target (infinite for kInvalidInput)
  int iterations = 0;
  IkStatus status = IkStatus::kInvalidInput;
  bool reached() const { return status == IkStatus::kReached; }
};

IkResult solveTipPosition(const Chain& chain, const Eigen::Vector3d& target,
                          const Eigen::VectorXd& seed, const IkOptions& options = {});

// The variables of the trocar chain that place the tip: yaw, pitch and insertion (roll and
// jaw spin the tip about the shaft). Throws std::invalid_argument when one is missing.
std::vector<int> trocarPositionVariables(const Chain& chain);

}  // namespace tt::kin
