#include "tissue_trainer/core/kinematics/tip_ik.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tt::kin {
namespace {

double distance(const Chain& chain, const Eigen::VectorXd& q, const Eigen::Vector3d& target) {
  return (target - chain.tipPose(q).translation()).norm();
}

// One damped least-squares step over the free variables; variables at a limit whose step
// points outward are frozen and the step recomputed.
Eigen::VectorXd dlsStep(const Chain& chain, const Eigen::VectorXd& q, const Eigen::Vector3d& e,
                        const std::vector<int>& vars, double lambda) {
  const Jacobian full = chain.tipJacobian(q);
  std::vector<bool> frozen(vars.size(), false);
  Eigen::VectorXd dq = Eigen::VectorXd::Zero(q.size());
  for (size_t pass = 0; pass <= vars.size(); ++pass) {
    Eigen::Matrix3Xd jac(3, vars.size());
    for (size_t k = 0; k < vars.size(); ++k)
      jac.col(k) = frozen[k] ? Eigen::Vector3d::Zero() : Eigen::Vector3d(full.block<3, 1>(0, vars[k]));
    const Eigen::Matrix3d a = jac * jac.transpose() + lambda * lambda * Eigen::Matrix3d::Identity();
    const Eigen::VectorXd step = jac.transpose() * a.ldlt().solve(e);
    bool changed = false;
    for (size_t k = 0; k < vars.size(); ++k) {
      const Variable& v = chain.variables()[vars[k]];
      const double x = q[vars[k]];
      if (!frozen[k] && ((x <= v.lower && step[k] < 0) || (x >= v.upper && step[k] > 0))) {
        frozen[k] = true;
        changed = true;
      }
    }
    if (!changed) {
      dq.setZero();
      for (size_t k = 0; k < vars.size(); ++k) dq[vars[k]] = step[k];
      break;
    }
  }
  return dq;
}

}  // namespace

IkResult solveTipPosition(const Chain& chain, const Eigen::Vector3d& target,
                          const Eigen::VectorXd& seed, const IkOptions& options) {
  IkResult result;
  result.q = seed.size() == chain.numVariables() ? chain.clamp(seed)
                                                  : chain.clamp(Eigen::VectorXd::Zero(chain.numVariables()));
  result.error = std::numeric_limits<double>::infinity();
  std::vector<int> vars = options.variables;
  if (vars.empty())
    for (int i = 0; i < chain.numVariables(); ++i) vars.push_back(i);
  for (int v : vars)
    if (v < 0 || v >= chain.numVariables()) return result;
  if (!target.allFinite() || !seed.allFinite() || seed.size() != chain.numVariables() ||
      !(options.damping >= 0.0) || !(options.tolerance > 0.0))
    return result;

  double err = distance(chain, result.q, target);
  const double lambda = std::isfinite(options.damping) ? options.damping : 1e-3;
  int it = 0;
  for (; it < options.maxIterations && err > options.tolerance; ++it) {
    const Eigen::Vector3d e = target - chain.tipPose(result.q).translation();
    const Eigen::VectorXd dq = dlsStep(chain, result.q, e, vars, lambda);
    if (!dq.allFinite() || dq.norm() < 1e-14) break;
    // Backtracking: accept the first step length that brings the tip nearer.
    bool improved = false;
    for (double s = 1.0; s > 1e-4; s *= 0.5) {
      const Eigen::VectorXd trial = chain.clamp(result.q + s * dq);
      const double trialErr = distance(chain, trial, target);
      if (trialErr < err) {
        result.q = trial;
        improved = err - trialErr > 1e-15;
        err = trialErr;
        break;
      }
    }
    if (!improved) break;
  }
  result.error = err;
  result.iterations = it;
  result.status = err <= options.tolerance ? IkStatus::kReached : IkStatus::kUnreachable;
  return result;
}

std::vector<int> trocarPositionVariables(const Chain& chain) {
  std::vector<int> out;
  for (const char* name : {"yaw", "pitch", "insertion"}) {
    const int i = chain.variableIndex(name);
    if (i < 0)
      throw std::invalid_argument(std::string("kinematic chain: no joint variable '") + name + "'");
    out.push_back(i);
  }
  return out;
}

}  // namespace tt::kin
