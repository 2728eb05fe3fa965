#include "tissue_trainer/core/fit/landmark_fit.h"

#include <Eigen/QR>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "tissue_trainer/core/model/activated_force_model.h"

namespace tt {

namespace {

constexpr int kAffine = 12;  // 9 entries of M (row-major) and 3 of t

// Orthogonality rows w (M^T M - I)_ab, a <= b, and their derivatives by the M entries.
void orthogonalityRows(const Eigen::Matrix3d& M, double w, int row, int column,
                       Eigen::VectorXd& r, Eigen::MatrixXd* J) {
  const Eigen::Matrix3d E = M.transpose() * M - Eigen::Matrix3d::Identity();
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b, ++row) {
      r[row] = w * E(a, b);
      if (!J) continue;
      // d(M^T M)_ab / dM_ij = delta_ja M_ib + delta_jb M_ia.
      for (int i = 0; i < 3; ++i) {
        (*J)(row, column + 3 * i + a) += w * M(i, b);
        (*J)(row, column + 3 * i + b) += w * M(i, a);
      }
    }
}

void unpackAffine(const Eigen::VectorXd& theta, int at, Eigen::Matrix3d& M, Eigen::Vector3d& t) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) M(i, j) = theta[at + 3 * i + j];
  t = theta.segment<3>(at + 9);
}

void packAffine(const Eigen::Matrix3d& M, const Eigen::Vector3d& t, int at, Eigen::VectorXd& theta) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) theta[at + 3 * i + j] = M(i, j);
  theta.segment<3>(at + 9) = t;
}

}  // namespace

const char* stopName(FitStop stop) {
  switch (stop) {
    case FitStop::kResidual: return "residual";
    case FitStop::kStep: return "step";
    case FitStop::kIterationLimit: return "iteration_limit";
    case FitStop::kNoDecrease: return "no_decrease";
    case FitStop::kEquilibriumFailed: return "equilibrium_failed";
  }
  return "unknown";
}

LandmarkFit::LandmarkFit(System& system, std::vector<Landmark> landmarks, FitParams params)
    : system_(system), landmarks_(std::move(landmarks)), params_(std::move(params)),
      solver_(params_.equilibrium) {
  for (const Landmark& l : landmarks_)
    for (int n : l.nodes)
      if (n < 0 || n >= system_.numNodes())
        throw std::invalid_argument("landmark node " + std::to_string(n) + " out of range");
  if (landmarks_.empty()) throw std::invalid_argument("no landmarks");
  for (const auto& m : system_.models)
    if (auto* a = dynamic_cast<ActivatedForceModel*>(m.get()))
      for (int i = 0; i < a->activationCount(); ++i) activations_.push_back({a, i});
  if (activations_.empty()) throw std::invalid_argument("the system has no activations to fit");
  if (params_.fitJaw) {
    if (params_.jawNodes.empty()) throw std::invalid_argument("jaw fitting without jaw nodes");
    jawRest_.resize(3, static_cast<int>(params_.jawNodes.size()));
    for (size_t k = 0; k < params_.jawNodes.size(); ++k) {
      const int n = params_.jawNodes[k];
      if (n < 0 || n >= system_.numNodes())
        throw std::invalid_argument("jaw node " + std::to_string(n) + " out of range");
      for (int d = 0; d < 3; ++d)
        if (!system_.isConstrained[3 * n + d])
          throw std::invalid_argument("jaw node " + std::to_string(n) +
                                      " has a free DOF: jaw nodes must be fixed on all axes");
      jawRest_.col(static_cast<int>(k)) = system_.state.x.segment<3>(3 * n);
    }
  }
}

int LandmarkFit::parameterCount() const {
  return activationCount() + (params_.fitJaw ? kAffine : 0) + (params_.fitCranium ? kAffine : 0);
}

std::string LandmarkFit::parameterName(int k) const {
  if (k < activationCount())
    return activations_[k].model->activationName(activations_[k].index);
  k -= activationCount();
  std::string prefix = "jaw";
  if (!params_.fitJaw || k >= kAffine) {
    prefix = "cranium";
    if (params_.fitJaw) k -= kAffine;
  }
  return k < 9 ? prefix + ".M" + std::to_string(k / 3) + std::to_string(k % 3)
               : prefix + ".t" + std::to_string(k - 9);
}

Eigen::VectorXd LandmarkFit::parameters() const {
  Eigen::VectorXd theta(parameterCount());
  for (int i = 0; i < activationCount(); ++i)
    theta[i] = activations_[i].model->activation(activations_[i].index);
  int at = activationCount();
  if (params_.fitJaw) packAffine(jawM_, jawT_, at, theta), at += kAffine;
  if (params_.fitCranium) packAffine(cranM_, cranT_, at, theta);
  return theta;
}

void LandmarkFit::setParameters(const Eigen::VectorXd& theta) {
  for (int i = 0; i < activationCount(); ++i)
    activations_[i].model->setActivation(activations_[i].index, theta[i]);
  int at = activationCount();
  if (params_.fitJaw) {
    unpackAffine(theta, at, jawM_, jawT_);
    at += kAffine;
    for (size_t k = 0; k < params_.jawNodes.size(); ++k)
      system_.state.x.segment<3>(3 * params_.jawNodes[k]) =
          jawM_ * jawRest_.col(static_cast<int>(k)) + jawT_;
  }
  if (params_.fitCranium) unpackAffine(theta, at, cranM_, cranT_);
}

Eigen::VectorXd LandmarkFit::landmarkPositions(const Eigen::VectorXd& x) const {
  return landmarkColumn(x);
}

Eigen::VectorXd LandmarkFit::landmarkColumn(const Eigen::VectorXd& dx) const {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(3 * static_cast<int>(landmarks_.size()));
  for (size_t l = 0; l < landmarks_.size(); ++l)
    for (int k = 0; k < 4; ++k)
      y.segment<3>(3 * l) += landmarks_[l].weights[k] * dx.segment<3>(3 * landmarks_[l].nodes[k]);
  return y;
}

bool LandmarkFit::evaluate(const Eigen::VectorXd& theta, Eigen::VectorXd& y, Eigen::MatrixXd* J) {
  setParameters(theta);
  equilibrium_ = solver_.solve(system_, system_.state.x);
  system_.state.v.setZero();
  if (!equilibrium_.converged()) {
    failure_ = "the equilibrium did not converge: " + equilibrium_.reason;
    return false;
  }
  const Eigen::VectorXd raw = landmarkPositions(system_.state.x);
  y.resize(raw.size());
  for (int l = 0; l < raw.size() / 3; ++l)
    y.segment<3>(3 * l) = cranM_ * raw.segment<3>(3 * l) + cranT_;
  if (J && !jacobian(raw, *J)) {
    failure_ = "the stiffness at the equilibrium could not be factored";
    return false;
  }
  return true;
}

// raw: landmark positions before the cranium post-transform.
bool LandmarkFit::jacobian(const Eigen::VectorXd& raw, Eigen::MatrixXd& J) {
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  };
  const Clock::time_point start = Clock::now();
  const Eigen::VectorXd& x = system_.state.x;
  const int n = system_.numDofs();
  J.setZero(raw.size(), parameterCount());
  SparseMatrix K;
  system_.assembleStiffness(x, K, -1.0);  // K = -df/dx

  // Right sides over all DOFs (free rows only) and the known constrained parts of each column.
  const int jawColumns = params_.fitJaw ? kAffine : 0;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, activationCount() + jawColumns);
  Eigen::MatrixXd known = Eigen::MatrixXd::Zero(n, rhs.cols());
  for (int i = 0; i < activationCount(); ++i) {
    Eigen::VectorXd fi = Eigen::VectorXd::Zero(n);
    activations_[i].model->addActiveForce(activations_[i].index, x, fi);
    rhs.col(i) = fi;  // Eq. 6: K_ff dx_f/da_i = f_i
  }
  for (int p = 0; p < jawColumns; ++p) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    for (size_t k = 0; k < params_.jawNodes.size(); ++k) {
      const int node = params_.jawNodes[k];
      if (p < 9)
        d[3 * node + p / 3] = jawRest_(p % 3, static_cast<int>(k));  // dM_ij: e_i x0_j
      else
        d[3 * node + p - 9] = 1.0;
    }
    known.col(activationCount() + p) = d;
    rhs.col(activationCount() + p) = -(K * d);  // Eq. 9: K_ff dx_f/dp = -K_fc dx_c/dp
  }
  for (int c = 0; c < rhs.cols(); ++c) {
    Eigen::VectorXd col = rhs.col(c);
    system_.zeroConstrained(col);
    rhs.col(c) = col;
  }
  system_.constrainMatrix(K);
  const Clock::time_point assembled = Clock::now();
  // One factorisation for all columns: CHOLMOD's supernodal L L^T (its analysis kept between
  // iterations), or Eigen's L D L^T where K_ff is not positive definite.
  if (!jacobianFactor_) jacobianFactor_ = std::make_unique<CholeskyPreconditioner>(false);
  Eigen::MatrixXd dx(n, rhs.cols());
  Clock::time_point factored;
  if (jacobianFactor_->factorNow(K)) {
    factored = Clock::now();
    Eigen::VectorXd column(n), solved(n);
    for (int c = 0; c < rhs.cols(); ++c) {
      column = rhs.col(c);
      jacobianFactor_->apply(column, solved);
      dx.col(c) = solved;
    }
  } else {
    const Eigen::SparseMatrix<double> Kc = K;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(Kc);
    if (factor.info() != Eigen::Success) return false;
    factored = Clock::now();
    dx = factor.solve(rhs);
  }
  dx += known;
  for (int c = 0; c < dx.cols(); ++c) J.col(c) = landmarkColumn(dx.col(c));
  if (params_.fitCranium) {
    const int at = activationCount() + jawColumns;
    for (int l = 0; l < raw.size() / 3; ++l) {
      J.block(3 * l, 0, 3, at) = cranM_ * J.block(3 * l, 0, 3, at).eval();
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) J(3 * l + i, at + 3 * i + j) = raw[3 * l + j];
        J(3 * l + i, at + 9 + i) = 1.0;
      }
    }
  }
  jacobianCost_ = {seconds(start, assembled), seconds(assembled, factored),
                   seconds(factored, Clock::now()), static_cast<int>(rhs.cols())};
  return true;
}

void LandmarkFit::stackedResidual(const Eigen::VectorXd& y, const Eigen::MatrixXd* J,
                                  Eigen::VectorXd& r, Eigen::MatrixXd* Jr) const {
  const int m = static_cast<int>(y.size());
  const int extra = 6 * ((params_.fitJaw ? 1 : 0) + (params_.fitCranium ? 1 : 0));
  r.resize(m + extra);
  for (size_t l = 0; l < landmarks_.size(); ++l)
    r.segment<3>(3 * l) = y.segment<3>(3 * l) - landmarks_[l].target;
  if (Jr) {
    Jr->setZero(m + extra, parameterCount());
    Jr->topRows(m) = *J;
  }
  int row = m, column = activationCount();
  const double w = params_.orthogonalityWeight;
  if (params_.fitJaw) orthogonalityRows(jawM_, w, row, column, r, Jr), row += 6, column += kAffine;
  if (params_.fitCranium) orthogonalityRows(cranM_, w, row, column, r, Jr);
}

double LandmarkFit::rms(const Eigen::VectorXd& y) const {
  double sum = 0.0;
  for (size_t l = 0; l < landmarks_.size(); ++l)
    sum += (y.segment<3>(3 * l) - landmarks_[l].target).squaredNorm();
  return std::sqrt(sum / static_cast<double>(landmarks_.size()));
}

Eigen::VectorXd LandmarkFit::projected(Eigen::VectorXd theta) const {
  for (int i = 0; i < activationCount(); ++i) theta[i] = std::clamp(theta[i], 0.0, 1.0);
  return theta;
}

Eigen::VectorXd LandmarkFit::boundedStep(const Eigen::MatrixXd& J, const Eigen::VectorXd& r,
                                         const Eigen::VectorXd& theta) const {
  const int P = parameterCount();
  // Held first: activations at a bound where the cost's gradient J^T r points outward.
  std::vector<bool> held(P, false);
  const Eigen::VectorXd gradient = J.transpose() * r;
  for (int i = 0; i < activationCount(); ++i)
    held[i] = (theta[i] <= 0.0 && gradient[i] > 0.0) || (theta[i] >= 1.0 && gradient[i] < 0.0);
  Eigen::VectorXd step = Eigen::VectorXd::Zero(P);
  for (int pass = 0; pass <= activationCount(); ++pass) {
    std::vector<int> free;
    for (int k = 0; k < P; ++k)
      if (!held[k]) free.push_back(k);
    const int F = static_cast<int>(free.size());
    step.setZero();
    if (F == 0) break;  // every parameter held at its bound
    const double lambda = params_.levenbergMarquardt;
    // J_free dtheta = -r, with Marquardt's rows sqrt(lambda) diag(|J_k|) below it.
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(J.rows() + (lambda > 0 ? F : 0), F);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(A.rows());
    b.head(r.size()) = -r;
    for (int c = 0; c < F; ++c) {
      A.col(c).head(J.rows()) = J.col(free[c]);
      if (lambda > 0) A(J.rows() + c, c) = std::sqrt(lambda) * std::max(J.col(free[c]).norm(), 1e-300);
    }
    const Eigen::VectorXd s = A.colPivHouseholderQr().solve(b);
    for (int c = 0; c < F; ++c) step[free[c]] = s[c];
    // Then any activation at a bound that the step pushes outward, and the rest re-solved.
    bool changed = false;
    for (int i = 0; i < activationCount(); ++i)
      if (!held[i] && ((theta[i] <= 0.0 && step[i] < 0.0) || (theta[i] >= 1.0 && step[i] > 0.0)))
        held[i] = changed = true;
    if (!changed) break;
  }
  return step;
}

FitResult LandmarkFit::run() {
  return runImpl({});
}

FitResult LandmarkFit::runImpl(const std::function<void(int, const FitIteration&)>& onIteration) {
  FitResult result;
  Eigen::VectorXd theta = projected(parameters()), y, r, trialY, trialR;
  Eigen::MatrixXd J, Jr;
  const auto equilibriumFailed = [&]() {
    result.stop = FitStop::kEquilibriumFailed;
    result.reason = failure_;
    return result;
  };
  if (!evaluate(theta, y, &J)) return equilibriumFailed();
  stackedResidual(y, &J, r, &Jr);
  double cost = 0.5 * r.squaredNorm();
  result.initialResidual = result.residual = rms(y);
  for (int it = 0;; ++it) {
    if (result.residual <= params_.residualTolerance) {
      result.stop = FitStop::kResidual;
      result.reason = "RMS landmark distance below the tolerance";
      break;
    }
    if (it >= params_.maxIterations) {
      result.stop = FitStop::kIterationLimit;
      result.reason = "iteration limit of " + std::to_string(params_.maxIterations) +
                      " reached with RMS landmark distance " + std::to_string(result.residual) + " m";
      break;
    }
    const Eigen::VectorXd step = boundedStep(Jr, r, theta);
    const Eigen::VectorXd full = projected(theta + step);
    if ((full - theta).lpNorm<Eigen::Infinity>() <= params_.stepTolerance) {
      result.stop = FitStop::kStep;
      result.reason = "step below the tolerance";
      break;
    }
    // Halve the step until the cost decreases; a trial whose equilibrium fails counts as one
    // that does not, and the next starts from the accepted state again.
    bool accepted = false;
    Eigen::VectorXd trial;
    const Eigen::VectorXd acceptedState = system_.state.x;
    double scale = 1.0, trialCost = cost;
    for (int h = 0; h <= params_.maxStepHalvings && !accepted; ++h, scale *= 0.5) {
      trial = projected(theta + scale * step);
      if (!evaluate(trial, trialY, nullptr)) {
        system_.state.x = acceptedState;
        continue;
      }
      stackedResidual(trialY, nullptr, trialR, nullptr);
      trialCost = 0.5 * trialR.squaredNorm();
      accepted = trialCost < cost;
    }
    if (!accepted) {
      if (!evaluate(theta, y, nullptr)) return equilibriumFailed();
      result.stop = FitStop::kNoDecrease;
      result.reason = "no step length along the Gauss-Newton step lowered the cost";
      break;
    }
    FitIteration record;
    record.step = (trial - theta).lpNorm<Eigen::Infinity>();
    theta = trial;
    y = trialY;
    cost = record.cost = trialCost;
    record.residual = result.residual = rms(y);
    if (!jacobian(landmarkPositions(system_.state.x), J)) {
      failure_ = "the stiffness at the equilibrium could not be factored";
      return equilibriumFailed();
    }
    stackedResidual(y, &J, r, &Jr);
    result.iterations.push_back(record);
    if (onIteration) onIteration(it + 1, record);
  }
  return result;
}

Eigen::VectorXd LandmarkFit::fittedPositions() const {
  Eigen::VectorXd x = system_.state.x;
  for (int n = 0; n < system_.numNodes(); ++n)
    x.segment<3>(3 * n) = cranM_ * x.segment<3>(3 * n) + cranT_;
  return x;
}

}  // namespace tt
