#include "tissue_trainer/core/integrate/radau_iia.h"

#include <Eigen/LU>
#include <Eigen/UmfPackSupport>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

namespace tt {

namespace {

using Complex = std::complex<double>;
using RealMatrix = Eigen::SparseMatrix<double>;      // column-major, for UMFPACK
using ComplexMatrix = Eigen::SparseMatrix<Complex>;  // same structure
using ComplexVector = Eigen::VectorXcd;
constexpr double kRoundoff = std::numeric_limits<double>::epsilon();
// A Newton contraction below this lets the next step keep the Jacobian.
constexpr double kThetaReuse = 1e-3;
constexpr double kSimplifiedTheta = 0.3;

struct NewtonOutcome {
  bool converged = false;
  double stepFactor = 0.5;  // on failure: next h = stepFactor * h
  double theta = kThetaReuse;
  int iterations = 0;
};

// The eigenvalues of a real 3 x 3 matrix with one real eigenvalue gamma and a complex pair
// alpha +- i beta (A^-1 of the 3-stage Radau IIA tableau), from its characteristic polynomial
// p(z) = z^3 - t z^2 + m z - d: gamma by Newton's method from above (p is convex right of
// (gamma + 2 alpha) / 3 < gamma, so the iterates fall monotonically to gamma), the pair from
// p(z) / (z - gamma) = z^2 - (t - gamma) z + d / gamma. Eigen's EigenSolver would do the same
// job and take 12 s of g++'s time to compile.
struct RadauEigenvalues {
  double gamma, alpha, beta;
};

RadauEigenvalues radauEigenvalues(const Eigen::Matrix3d& M) {
  const double t = M.trace();
  const double m = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0) + M(0, 0) * M(2, 2) -
                   M(0, 2) * M(2, 0) + M(1, 1) * M(2, 2) - M(1, 2) * M(2, 1);
  const double d = M.determinant();
  double z = M.cwiseAbs().rowwise().sum().maxCoeff();  // >= the spectral radius >= gamma
  for (int i = 0; i < 100; ++i) {
    const double step = (((z - t) * z + m) * z - d) / ((3.0 * z - 2.0 * t) * z + m);
    z -= step;
    if (std::abs(step) <= 1e-15 * z) break;
  }
  RadauEigenvalues e;
  e.gamma = z;
  e.alpha = 0.5 * (t - z);
  e.beta = std::sqrt(d / z - e.alpha * e.alpha);
  return e;
}

// A vector spanning the null space of a singular 3 x 3 matrix S (real or complex) of rank 2:
// the (unconjugated) cross product of two of its rows, the pair giving the longest one.
template <class Scalar>
Eigen::Matrix<std::complex<double>, 3, 1> nullVector(const Eigen::Matrix<Scalar, 3, 3>& S) {
  Eigen::Matrix<Scalar, 3, 1> best = Eigen::Matrix<Scalar, 3, 1>::Zero();
  for (int i = 0; i < 3; ++i) {
    const Eigen::Matrix<Scalar, 3, 1> r1 = S.row(i).transpose();
    const Eigen::Matrix<Scalar, 3, 1> r2 = S.row((i + 1) % 3).transpose();
    const Eigen::Matrix<Scalar, 3, 1> v(r1[1] * r2[2] - r1[2] * r2[1],
                                        r1[2] * r2[0] - r1[0] * r2[2],
                                        r1[0] * r2[1] - r1[1] * r2[0]);
    if (v.norm() > best.norm()) best = v;
  }
  return best.template cast<std::complex<double>>() / best.norm();
}

RadauTableau buildTableau() {
  RadauTableau r;
  const double s6 = std::sqrt(6.0);
  r.c << (4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0;
  // Collocation: sum_j a_ij c_j^(k-1) = c_i^k / k for k = 1..3, i.e. A V = W.
  Eigen::Matrix3d V, W;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      V(i, k) = std::pow(r.c[i], k);
      W(i, k) = std::pow(r.c[i], k + 1) / (k + 1);
    }
  r.A = W * V.inverse();
  r.b = r.A.row(2).transpose();  // stiffly accurate: c_3 = 1
  r.Ainv = r.A.inverse();

  // Eigenvalue alpha - i beta with eigenvector a + i b: A^-1 a = alpha a + beta b and
  // A^-1 b = -beta a + alpha b, so T = [u, a, b] gives the block form of D.17.
  const RadauEigenvalues eig = radauEigenvalues(r.Ainv);
  r.gamma = eig.gamma;
  r.alpha = eig.alpha;
  r.beta = eig.beta;
  r.T.col(0) = nullVector<double>(r.Ainv - r.gamma * Eigen::Matrix3d::Identity()).real();
  const Eigen::Vector3cd ab = nullVector<std::complex<double>>(
      r.Ainv.cast<std::complex<double>>() -
      std::complex<double>(r.alpha, -r.beta) * Eigen::Matrix3cd::Identity());
  r.T.col(1) = ab.real();
  r.T.col(2) = ab.imag();
  r.Tinv = r.T.inverse();

  // Embedded method y_hat = y0 + h (gamma0 F(y0) + sum b_hat_i F_i) of order 3 with
  // gamma0 = 1 / gamma: delta = b_hat - b solves V^T delta = (-gamma0, 0, 0); h F_i = A^-1 Z.
  const Eigen::Vector3d delta = V.transpose().lu().solve(Eigen::Vector3d(-1.0 / r.gamma, 0, 0));
  r.errorWeights = r.Ainv.transpose() * delta;
  return r;
}

}  // namespace

const RadauTableau& RadauTableau::get() {
  static const RadauTableau tableau = buildTableau();
  return tableau;
}

Eigen::Matrix3d RadauTableau::extrapolation(double ratio) const {
  const double nodes[4] = {0.0, c[0], c[1], c[2]};
  Eigen::Matrix3d P;
  for (int i = 0; i < 3; ++i) {
    const double s = 1.0 + ratio * c[i];
    for (int j = 1; j <= 3; ++j) {
      double basis = 1.0;  // Lagrange basis of node j on {0, c1, c2, c3}
      for (int m = 0; m <= 3; ++m)
        if (m != j) basis *= (s - nodes[m]) / (nodes[j] - nodes[m]);
      P(i, j - 1) = basis - (j == 3 ? 1.0 : 0.0);
    }
  }
  return P;
}

// Everything a frame needs, allocated once per system.
struct RadauIIA::Workspace {
  const RadauTableau& tab = RadauTableau::get();
  const System* system = nullptr;
  int n = 0;        // DOFs (positions), the state has 2n entries
  long nnz = 0;     // entries of the system pattern
  bool simplified = false;

  // Per-frame data.
  Eigen::VectorXd invMass;
  std::vector<int> constrained;
  int freeComponents = 0;
  double relTol = 0.0;
  Eigen::VectorXd absTol;  // 2n
  double newtonTol = 0.0;

  // Scratch for force evaluation.
  Eigen::VectorXd xs, vs, fs, f0;

  // Jacobian: K = df/dx and D = df/dv in column-major pattern form.
  SparseMatrix rowMajor, velocityRowMajor;
  std::vector<int> rowToCol;        // value index map RowMajor -> ColMajor
  RealMatrix K, D;
  std::vector<int> diagonal;        // value index of (j, j) in column-major
  std::vector<std::vector<int>> colourGroups;  // DOFs perturbed together
  std::vector<int> identityOffDiagonal;        // entries zeroed for constrained DOFs
  Eigen::VectorXd dampingDiagonal;  // simplified mode: df/dv = -diag(c)

  // Linear systems (sigma^2 M - sigma D - K) for sigma = gamma / h and (alpha + i beta) / h.
  RealMatrix realSystem;
  ComplexMatrix complexSystem;
  Eigen::UmfPackLU<RealMatrix> realLU;
  Eigen::UmfPackLU<ComplexMatrix> complexLU;
  Eigen::VectorXd realDiagonal;     // simplified mode
  ComplexVector complexDiagonal;
  double factoredStep = -1.0;
  bool analysed = false;

  // Stage data: columns are the three stages, rows the 2n state entries.
  Eigen::MatrixXd Z, F, G, R, dW, dZ, lastZ, prescribedZ;
  Eigen::VectorXd y0, y1, F0, stage, err, rhs, scratch;
  Eigen::VectorXd rp, rv, dp, Dr;
  ComplexVector crp, crv, cdp, crhs, cDr;

  // Step-size history.
  bool hasHistory = false;
  double lastStep = 0.0;    // size of the last accepted step (for extrapolation)
  double lastTime = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd lastEnd;  // state at the end of the last frame
  double faccon = 1.0;
  // Jacobian reuse: evaluate it at the next attempt; it was evaluated for this step.
  bool needJacobian = true, freshJacobian = false;
  double theta = kThetaReuse;  // Newton contraction of the last converged attempt

  void setup(const System& sys, RadauJacobian mode);
  void prepareFrame(const System& sys, const RadauOptions& options);
  bool derivative(double t, const Eigen::VectorXd& y, Eigen::Ref<Eigen::VectorXd> out,
                  RadauStatistics& stats);
  void jacobian(const Eigen::VectorXd& y, RadauJacobian mode, RadauStatistics& stats);
  bool factor(double h);
  void solveReal(double h, const Eigen::Ref<const Eigen::VectorXd>& r,
                 Eigen::Ref<Eigen::VectorXd> out);
  void solveComplex(double h, const Eigen::Ref<const Eigen::VectorXd>& r2,
                    const Eigen::Ref<const Eigen::VectorXd>& r3,
                    Eigen::Ref<Eigen::VectorXd> out2, Eigen::Ref<Eigen::VectorXd> out3);
  void prescribeStages(double t, double h);
  void startingValues(double t, double h);
  void applyPrescribed();
  NewtonOutcome newton(double t, double h, int maxIterations, StepReport& report,
                       RadauStatistics& stats);
  double estimateError(double t, double h, bool refine, StepReport& report,
                       RadauStatistics& stats);
  void zeroConstrainedRows(Eigen::Ref<Eigen::MatrixXd> m) const;
  double weightedNorm(const Eigen::Ref<const Eigen::MatrixXd>& m,
                      const Eigen::VectorXd& ya, const Eigen::VectorXd& yb) const;
};

void RadauIIA::Workspace::setup(const System& sys, RadauJacobian mode) {
  n = sys.numDofs();
  simplified = mode == RadauJacobian::kSimplified;
  system = &sys;
  xs.resize(n); vs.resize(n); fs.resize(n); f0.resize(n);
  Z.setZero(2 * n, 3); F = G = R = dW = dZ = lastZ = Z;
  hasHistory = false;
  analysed = false;
  factoredStep = -1.0;
  if (simplified) {
    nnz = 0;
    return;
  }
  rowMajor = sys.pattern.zeroMatrix();
  velocityRowMajor = rowMajor;
  nnz = rowMajor.nonZeros();
  // Carry value indices through the storage-order conversion to map one onto the other.
  SparseMatrix indexed = rowMajor;
  for (long k = 0; k < nnz; ++k) indexed.valuePtr()[k] = static_cast<double>(k);
  RealMatrix indexedCol = indexed;
  rowToCol.assign(nnz, 0);
  for (long k = 0; k < nnz; ++k) rowToCol[static_cast<long>(indexedCol.valuePtr()[k])] = k;
  K = indexedCol;
  K.coeffs().setZero();
  D = K;
  diagonal.assign(n, -1);
  for (int j = 0; j < n; ++j)
    for (RealMatrix::InnerIterator it(K, j); it; ++it)
      if (it.row() == j) diagonal[j] = static_cast<int>(&it.valueRef() - K.valuePtr());
  realSystem = K;
  complexSystem = K.cast<Complex>();

  // Distance-2 colouring of the nodes: nodes of one colour share no matrix row, so one force
  // evaluation per colour and axis gives all their columns of the finite-difference Jacobian.
  if (mode != RadauJacobian::kNumerical) return;
  const int nodes = n / 3;
  std::vector<std::vector<int>> neighbours(nodes);
  for (int a = 0; a < nodes; ++a) {
    for (RealMatrix::InnerIterator it(K, 3 * a); it; ++it) neighbours[a].push_back(it.row() / 3);
    std::sort(neighbours[a].begin(), neighbours[a].end());
    neighbours[a].erase(std::unique(neighbours[a].begin(), neighbours[a].end()),
                        neighbours[a].end());
  }
  std::vector<int> colour(nodes, -1), seen;
  int colours = 0;
  for (int a = 0; a < nodes; ++a) {
    seen.assign(colours + 1, 0);
    for (int b : neighbours[a])
      for (int d : neighbours[b])
        if (colour[d] >= 0) seen[colour[d]] = 1;
    colour[a] = static_cast<int>(std::find(seen.begin(), seen.end(), 0) - seen.begin());
    colours = std::max(colours, colour[a] + 1);
  }
  colourGroups.assign(3 * colours, {});
  for (int a = 0; a < nodes; ++a)
    for (int axis = 0; axis < 3; ++axis) colourGroups[3 * colour[a] + axis].push_back(3 * a + axis);
}

void RadauIIA::Workspace::prepareFrame(const System& sys, const RadauOptions& options) {
  constrained = sys.constrainedDofs;
  invMass = Eigen::VectorXd::Zero(n);
  for (int j = 0; j < n; ++j)
    if (!sys.isConstrained[j]) invMass[j] = 1.0 / sys.mass[j];
  freeComponents = 2 * (n - static_cast<int>(constrained.size()));
  // The error estimate is of order 3 while the solution is of order 5: a tighter internal
  // tolerance, growing like tol^(2/3), makes the achieved error follow the requested one.
  relTol = 0.1 * std::pow(options.relTol, 2.0 / 3.0);
  const double ratio = relTol / options.relTol;
  const double absVel = options.absTolVelocity > 0.0 ? options.absTolVelocity : options.absTol;
  absTol.resize(2 * n);
  absTol.head(n).setConstant(options.absTol * ratio);
  absTol.tail(n).setConstant(absVel * ratio);
  newtonTol = options.newtonTolerance > 0.0
                  ? options.newtonTolerance
                  : std::max(10.0 * kRoundoff / relTol, std::min(0.03, std::sqrt(relTol)));
  prescribedZ.resize(2 * static_cast<int>(constrained.size()), 3);
  if (simplified) {
    dampingDiagonal = -sys.damping;
    return;
  }
  identityOffDiagonal.clear();
  for (int j = 0; j < n; ++j)
    for (RealMatrix::InnerIterator it(K, j); it; ++it)
      if (it.row() != j && (sys.isConstrained[j] || sys.isConstrained[it.row()]))
        identityOffDiagonal.push_back(static_cast<int>(&it.valueRef() - K.valuePtr()));
}

bool RadauIIA::Workspace::derivative(double t, const Eigen::VectorXd& y,
                                     Eigen::Ref<Eigen::VectorXd> out, RadauStatistics& stats) {
  (void)t;  // the system is autonomous apart from its prescribed DOFs
  xs = y.head(n);
  vs = y.tail(n);
  system->computeForce(xs, vs, fs);
  ++stats.forceEvaluations;
  out.head(n) = vs;
  out.tail(n) = fs.cwiseProduct(invMass);
  for (int dof : constrained) out[dof] = out[n + dof] = 0.0;
  return out.allFinite();
}

void RadauIIA::Workspace::jacobian(const Eigen::VectorXd& y, RadauJacobian mode,
                                   RadauStatistics& stats) {
  if (mode == RadauJacobian::kAnalytical) {
    xs = y.head(n);
    system->assembleStiffness(xs, rowMajor);
    for (long k = 0; k < nnz; ++k) K.valuePtr()[rowToCol[k]] = rowMajor.valuePtr()[k];
    D.coeffs().setZero();
    for (int j = 0; j < n; ++j) D.valuePtr()[diagonal[j]] = -system->damping[j];
    if (system->hasVelocityJacobian()) {  // the models' own damping and friction
      vs = y.tail(n);
      system->assembleVelocityJacobian(xs, vs, velocityRowMajor);
      for (long k = 0; k < nnz; ++k) D.valuePtr()[rowToCol[k]] += velocityRowMajor.valuePtr()[k];
    }
    return;
  }
  // Forward differences, one colour group at a time, in positions then velocities.
  xs = y.head(n);
  vs = y.tail(n);
  system->computeForce(xs, vs, f0);
  ++stats.forceEvaluations;
  for (int which = 0; which < 2; ++which) {
    RealMatrix& M = which == 0 ? K : D;
    Eigen::VectorXd& u = which == 0 ? xs : vs;
    for (const std::vector<int>& group : colourGroups) {
      for (int j : group) u[j] += std::sqrt(kRoundoff * std::max(1e-5, std::abs(u[j])));
      system->computeForce(xs, vs, fs);
      ++stats.forceEvaluations;
      for (int j : group) {
        const double step = u[j] - y[which * n + j];
        u[j] = y[which * n + j];
        for (RealMatrix::InnerIterator it(M, j); it; ++it)
          it.valueRef() = (fs[it.row()] - f0[it.row()]) / step;
      }
    }
  }
}

bool RadauIIA::Workspace::factor(double h) {
  const double sr = tab.gamma / h;
  const Complex sc = Complex(tab.alpha, tab.beta) / h;
  const Eigen::VectorXd& mass = system->mass;
  if (simplified) {
    realDiagonal = sr * sr * mass - sr * dampingDiagonal;
    complexDiagonal = sc * sc * mass.cast<Complex>() - sc * dampingDiagonal.cast<Complex>();
    for (int dof : constrained) realDiagonal[dof] = 1.0, complexDiagonal[dof] = 1.0;
    factoredStep = h;
    return realDiagonal.allFinite() && complexDiagonal.allFinite();
  }
  const long count = K.nonZeros();
  double* re = realSystem.valuePtr();
  Complex* co = complexSystem.valuePtr();
  const double* k = K.valuePtr();
  const double* d = D.valuePtr();
  for (long e = 0; e < count; ++e) {
    re[e] = -k[e] - sr * d[e];
    co[e] = -k[e] - sc * d[e];
  }
  for (int j = 0; j < n; ++j) {
    if (system->isConstrained[j]) {
      re[diagonal[j]] = 1.0;
      co[diagonal[j]] = 1.0;
    } else {
      re[diagonal[j]] += sr * sr * mass[j];
      co[diagonal[j]] += sc * sc * mass[j];
    }
  }
  for (int e : identityOffDiagonal) re[e] = 0.0, co[e] = 0.0;
  if (!analysed) {
    realLU.analyzePattern(realSystem);
    complexLU.analyzePattern(complexSystem);
    analysed = true;
  }
  realLU.factorize(realSystem);
  complexLU.factorize(complexSystem);
  factoredStep = h;
  return realLU.info() == Eigen::Success && complexLU.info() == Eigen::Success;
}

// (sigma I - J) (dp, dv) = (rp, rv) with J = [[0, I], [M^-1 K, M^-1 D]]:
// (sigma^2 M - sigma D - K) dp = M rv + (sigma M - D) rp and dv = sigma dp - rp.
void RadauIIA::Workspace::solveReal(double h, const Eigen::Ref<const Eigen::VectorXd>& r,
                                    Eigen::Ref<Eigen::VectorXd> out) {
  const double s = tab.gamma / h;
  const Eigen::VectorXd& mass = system->mass;
  rp = r.head(n);
  rv = r.tail(n);
  if (simplified) Dr = dampingDiagonal.cwiseProduct(rp);
  else Dr = D * rp;
  rhs = mass.cwiseProduct(rv + s * rp) - Dr;
  for (int dof : constrained) rhs[dof] = 0.0;
  if (simplified) dp = rhs.cwiseQuotient(realDiagonal);
  else dp = realLU.solve(rhs);
  out.head(n) = dp;
  out.tail(n) = s * dp - rp;
  for (int dof : constrained) out[dof] = out[n + dof] = 0.0;
}

void RadauIIA::Workspace::solveComplex(double h, const Eigen::Ref<const Eigen::VectorXd>& r2,
                                       const Eigen::Ref<const Eigen::VectorXd>& r3,
                                       Eigen::Ref<Eigen::VectorXd> out2,
                                       Eigen::Ref<Eigen::VectorXd> out3) {
  const Complex s = Complex(tab.alpha, tab.beta) / h;
  const Eigen::VectorXd& mass = system->mass;
  crp.resize(n);
  crv.resize(n);
  crp.real() = r2.head(n);
  crp.imag() = r3.head(n);
  crv.real() = r2.tail(n);
  crv.imag() = r3.tail(n);
  if (simplified) {
    cDr = dampingDiagonal.cast<Complex>().cwiseProduct(crp);
  } else {
    rp = crp.real();
    Dr = D * rp;
    cDr.resize(n);
    cDr.real() = Dr;
    rp = crp.imag();
    Dr = D * rp;
    cDr.imag() = Dr;
  }
  crhs = mass.cast<Complex>().cwiseProduct(crv + s * crp) - cDr;
  for (int dof : constrained) crhs[dof] = 0.0;
  if (simplified) cdp = crhs.cwiseQuotient(complexDiagonal);
  else cdp = complexLU.solve(crhs);
  out2.head(n) = cdp.real();
  out3.head(n) = cdp.imag();
  crv = s * cdp - crp;
  out2.tail(n) = crv.real();
  out3.tail(n) = crv.imag();
  for (int dof : constrained) out2[dof] = out2[n + dof] = out3[dof] = out3[n + dof] = 0.0;
}

void RadauIIA::Workspace::prescribeStages(double t, double h) {
  const int m = static_cast<int>(constrained.size());
  for (int i = 0; i < 3; ++i) {
    xs = y0.head(n);
    vs = y0.tail(n);
    system->prescribe(t + tab.c[i] * h, xs, vs);
    for (int k = 0; k < m; ++k) {
      const int dof = constrained[k];
      prescribedZ(k, i) = xs[dof] - y0[dof];
      prescribedZ(m + k, i) = vs[dof] - y0[n + dof];
    }
  }
}

void RadauIIA::Workspace::zeroConstrainedRows(Eigen::Ref<Eigen::MatrixXd> mat) const {
  for (int dof : constrained) {
    mat.row(dof).setZero();
    mat.row(n + dof).setZero();
  }
}

double RadauIIA::Workspace::weightedNorm(const Eigen::Ref<const Eigen::MatrixXd>& mat,
                                         const Eigen::VectorXd& ya,
                                         const Eigen::VectorXd& yb) const {
  if (freeComponents == 0) return 0.0;
  double sum = 0.0;
  for (int k = 0; k < 2 * n; ++k) {
    const double scale =
        absTol[k] + relTol * std::max(std::abs(ya[k]), std::abs(yb[k]));
    sum += mat.row(k).squaredNorm() / (scale * scale);
  }
  // Constrained rows are zero; average over the free components only.
  return std::sqrt(sum / (freeComponents * mat.cols()));
}

void RadauIIA::Workspace::applyPrescribed() {
  const int m = static_cast<int>(constrained.size());
  for (int k = 0; k < m; ++k) {
    Z.row(constrained[k]) = prescribedZ.row(k);
    Z.row(n + constrained[k]) = prescribedZ.row(m + k);
  }
}

// Starting values from the collocation polynomial of the last accepted step (D.19).
void RadauIIA::Workspace::startingValues(double t, double h) {
  prescribeStages(t, h);
  if (hasHistory) Z.noalias() = lastZ * tab.extrapolation(h / lastStep).transpose();
  else Z.setZero();
  applyPrescribed();
}

// Simplified Newton iterations on the transformed stage equations (D.16), with the
// convergence test and divergence prediction of Hairer & Wanner IV.8.
NewtonOutcome RadauIIA::Workspace::newton(double t, double h, int maxIterations,
                                          StepReport& report, RadauStatistics& stats) {
  NewtonOutcome out;
  faccon = std::pow(std::max(faccon, kRoundoff), 0.8);
  double previousNorm = 0.0, previousRatio = 0.0;
  for (int k = 0; k < maxIterations; ++k) {
    for (int i = 0; i < 3; ++i) {
      stage = y0 + Z.col(i);
      if (!derivative(t + tab.c[i] * h, stage, F.col(i), stats)) return out;
    }
    G.noalias() = F - (1.0 / h) * Z * tab.Ainv.transpose();
    zeroConstrainedRows(G);
    R.noalias() = G * tab.Tinv.transpose();
    solveReal(h, R.col(0), dW.col(0));
    solveComplex(h, R.col(1), R.col(2), dW.col(1), dW.col(2));
    report.linearIterations += 2;
    stats.linearSolves += 2;
    dZ.noalias() = dW * tab.T.transpose();
    ++out.iterations;
    const double norm = weightedNorm(dZ, y0, y0);
    if (!std::isfinite(norm)) return out;
    if (k >= 1) {
      const double ratio = norm / previousNorm;
      out.theta = k == 1 ? ratio : std::sqrt(ratio * previousRatio);
      previousRatio = ratio;
      if (out.theta >= 0.99) return out;
      faccon = out.theta / (1.0 - out.theta);
      // Would the remaining iterations reach the tolerance at this contraction rate?
      const int left = maxIterations - 1 - k;
      const double predicted = faccon * norm * std::pow(out.theta, left) / newtonTol;
      if (predicted >= 1.0) {
        out.stepFactor = 0.8 * std::pow(std::clamp(predicted, 1e-4, 20.0), -1.0 / (4.0 + left));
        return out;
      }
    }
    previousNorm = norm;
    Z += dZ;
    applyPrescribed();
    if (faccon * norm <= newtonTol) {
      out.converged = true;
      return out;
    }
  }
  return out;
}

// Embedded error estimate (D.21-D.22) filtered through (gamma/h I - J)^-1; weighted RMS norm.
double RadauIIA::Workspace::estimateError(double t, double h, bool refine, StepReport& report,
                                          RadauStatistics& stats) {
  const Eigen::Vector3d weights = (tab.gamma / h) * tab.errorWeights;
  y1 = y0 + Z.col(2);
  scratch = F0 + Z * weights;
  zeroConstrainedRows(scratch);
  err.resize(2 * n);
  solveReal(h, scratch, err);
  ++report.linearIterations;
  ++stats.linearSolves;
  double error = weightedNorm(err, y0, y1);
  if (error >= 1.0 && refine) {
    // Near a stiff transient the first estimate is too pessimistic; one more filtering
    // pass with F evaluated at y0 + err keeps the estimate bounded for large h |J|.
    stage = y0 + err;
    if (derivative(t, stage, F.col(0), stats)) {
      scratch = F.col(0) + Z * weights;
      zeroConstrainedRows(scratch);
      solveReal(h, scratch, err);
      ++report.linearIterations;
      ++stats.linearSolves;
      error = weightedNorm(err, y0, y1);
    }
  }
  return std::isfinite(error) ? error : 1e10;
}

namespace {

std::unique_ptr<StepSizeController> radauStepControl(const RadauOptions& o) {
  if (!o.adaptive)
    return std::make_unique<FixedStepControl>(FixedStepControl::ofLength(o.initialStep));
  ErrorStepParams p;
  p.initialStep = o.initialStep;
  p.minStep = o.minStep;
  p.maxStep = o.maxStep;
  p.estimatorOrder = 3;  // the embedded method of D.21-D.22
  p.safety = o.safety;
  p.maxGrowth = o.maxGrowth;
  p.maxShrink = o.maxShrink;
  p.newtonIterationLimit = o.maxNewtonIterations;
  return std::make_unique<ErrorStepControl>(p);
}

}  // namespace

RadauIIA::RadauIIA(RadauOptions options)
    : SteppedIntegrator(radauStepControl(options), options.maxStepsPerFrame),
      options_(options),
      work_(std::make_unique<Workspace>()) {}

RadauIIA::~RadauIIA() = default;

void RadauIIA::reset() {
  work_->hasHistory = false;
  work_->system = nullptr;  // rebuild the matrices on the next frame
}

FrameStart RadauIIA::beginFrame(System& system, double) {
  FrameStart start;
  Workspace& w = *work_;
  const RadauOptions& opt = options_;
  const bool simplified = opt.jacobian == RadauJacobian::kSimplified;
  if (w.system != &system || w.n != system.numDofs() || w.simplified != simplified ||
      (opt.jacobian == RadauJacobian::kNumerical && w.colourGroups.empty()))
    w.setup(system, opt.jacobian);
  w.prepareFrame(system, opt);
  const int n = w.n;
  for (int j = 0; j < n; ++j)
    if (!system.isConstrained[j] && !(system.mass[j] > 0.0)) {
      start.failure = "radau_iia: free DOF " + std::to_string(j) + " has no mass";
      return start;
    }
  if (opt.jacobian == RadauJacobian::kAnalytical && !system.hasStiffness()) {
    start.failure = "radau_iia: analytical Jacobian needs every model's stiffness";
    return start;
  }
  const double t = system.state.t;
  w.y0.resize(2 * n);
  w.xs = system.state.x;
  w.vs = system.state.v;
  system.prescribe(t, w.xs, w.vs);
  w.y0 << w.xs, w.vs;
  // Continue the step size and stage history only if nobody touched the state.
  start.continues =
      w.hasHistory && t == w.lastTime && w.lastEnd.size() == 2 * n && w.lastEnd == w.y0;
  if (!start.continues) {
    w.hasHistory = false;
    w.faccon = 1.0;
  }
  w.F0.resize(2 * n);
  if (!w.derivative(t, w.y0, w.F0, statistics_)) start.failure = "radau_iia: non-finite force";
  w.needJacobian = true;
  w.freshJacobian = false;
  return start;
}

StepAttempt RadauIIA::attempt(System&, const StepContext& step, StepReport& report) {
  StepAttempt out;
  Workspace& w = *work_;
  const double t = step.t, h = step.h;
  if (w.needJacobian) {
    if (!w.simplified) {
      w.jacobian(w.y0, options_.jacobian, statistics_);
      ++report.jacobians;
    }
    w.needJacobian = false;
    w.freshJacobian = true;
    w.factoredStep = -1.0;
  }
  if (h != w.factoredStep) {
    if (!w.factor(h)) {
      out.status = StepStatus::kFailed;
      out.failure = "radau_iia: singular Newton matrix";
      return out;
    }
    if (!w.simplified) ++statistics_.factorizations;
  }

  w.startingValues(t, h);
  const NewtonOutcome newton = w.newton(t, h, options_.maxNewtonIterations, report, statistics_);
  report.newtonIterations += newton.iterations;
  if (!newton.converged) {
    // A Jacobian from an earlier step may be what failed: evaluate it again.
    if (!w.freshJacobian && !w.simplified) w.needJacobian = true;
    out.status = StepStatus::kNotConverged;
    out.retryFactor = newton.stepFactor;
    out.failure = "radau_iia: Newton iteration did not converge";
    return out;
  }
  out.measure.error = w.estimateError(t, h, step.fresh || step.afterRejection, report,
                                      statistics_);
  out.measure.iterations = newton.iterations;
  w.theta = newton.theta;
  out.measure.sameStepIsCheap = !(newton.theta > kThetaReuse);
  if (w.simplified && newton.theta > kThetaReuse) {
    // Without the force terms the Newton contraction grows like h^2: cap the growth so the
    // next step still contracts by about kSimplifiedTheta.
    out.measure.nextStepCap = h * std::sqrt(kSimplifiedTheta / newton.theta);
  }
  return out;
}

std::string RadauIIA::accept(System& system, const StepContext& step) {
  Workspace& w = *work_;
  if (!w.y1.allFinite()) return "radau_iia: non-finite state";
  w.y0 = w.y1;
  if (!w.derivative(step.end, w.y0, w.F0, statistics_)) return "radau_iia: non-finite force";
  w.lastZ = w.Z;
  w.lastStep = step.h;
  w.hasHistory = true;
  w.freshJacobian = false;
  w.needJacobian = w.theta > kThetaReuse;
  system.state.x = w.y0.head(w.n);
  system.state.v = w.y0.tail(w.n);
  system.state.t = step.end;
  return "";
}

// The constrained DOFs take their prescribed values exactly at the frame's end; inside the
// frame the stages carry them.
void RadauIIA::abandonFrame(const System&) { work_->hasHistory = false; }

void RadauIIA::endFrame(System& system) {
  Workspace& w = *work_;
  system.prescribe(system.state.t, system.state.x, system.state.v);
  w.lastEnd.resize(2 * w.n);
  w.lastEnd << system.state.x, system.state.v;
  w.lastTime = system.state.t;
}

}  // namespace tt
