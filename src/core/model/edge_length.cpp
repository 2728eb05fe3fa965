#include "tissue_trainer/core/model/edge_length.h"

#include <Eigen/Geometry>
#include <cmath>

namespace tt {
namespace {

// Edge numbering: 01 02 03 12 13 23.
constexpr int kEdgeNodes[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
constexpr int kEdgeOf[4][4] = {{-1, 0, 1, 2}, {0, -1, 3, 4}, {1, 3, -1, 5}, {2, 4, 5, -1}};

// The two nodes other than a and b, in increasing order.
inline void otherTwo(int a, int b, int& k, int& m) {
  int found[2], n = 0;
  for (int i = 0; i < 4; ++i)
    if (i != a && i != b) found[n++] = i;
  k = found[0];
  m = found[1];
}

inline double edgeK(const EdgeLengthLiteralTet& t, int j, int k) { return t.K[kEdgeOf[j][k]]; }

}  // namespace

bool parseEdgeLengthPath(const std::string& name, EdgeLengthPath& path) {
  if (name == "fast") path = EdgeLengthPath::kFast;
  else if (name == "literal") path = EdgeLengthPath::kLiteral;
  else if (name == "eq30") path = EdgeLengthPath::kEq30;
  else return false;
  return true;
}

EdgeLengthLiteralTet makeEdgeLengthLiteralTet(const Eigen::Matrix3Xd& rest, const Tet& tet,
                                              const Eigen::Vector3d& fibre, const Material& m) {
  EdgeLengthLiteralTet t;
  const TetRest r = tetRest(rest, tet);
  double l2[4][4] = {};
  for (int e = 0; e < 6; ++e) {
    const int a = kEdgeNodes[e][0], b = kEdgeNodes[e][1];
    t.restSq[e] = (rest.col(tet[b]) - rest.col(tet[a])).squaredNorm();
    l2[a][b] = l2[b][a] = t.restSq[e];
  }
  for (int e = 0; e < 6; ++e) {  // Eq 20, with l, m the nodes off edge j-k
    const int j = kEdgeNodes[e][0], k = kEdgeNodes[e][1];
    int l, mm;
    otherTwo(j, k, l, mm);
    t.K[e] = (l2[l][mm] * (l2[j][l] + l2[k][l] + l2[j][mm] + l2[k][mm] - 2.0 * l2[j][k] - l2[l][mm]) -
              (l2[j][l] - l2[j][mm]) * (l2[k][l] - l2[k][mm])) /
             16.0;
  }
  for (int j = 0; j < 4; ++j) {
    int face[3], n = 0;
    for (int i = 0; i < 4; ++i)
      if (i != j) face[n++] = tet[i];
    const Eigen::Vector3d normal = (rest.col(face[1]) - rest.col(face[0]))
                                       .cross(rest.col(face[2]) - rest.col(face[0]));
    t.areaSq[j] = 0.25 * normal.squaredNorm();
    t.fibreGrad[j] = fibre.dot(r.grad.col(j));
  }
  t.volume = r.volume;
  const double v4 = std::pow(r.volume, 4);
  const ElasticConstants& k = m.elasticConstants();
  t.muScale = k.mu / (162.0 * v4);
  t.lambdaMuScale = (k.lambda + k.mu) / (162.0 * v4);
  t.c = k.fibreCoefficient();
  return t;
}

namespace {

// The six edges' L^2 - l^2 into d; returns their sum weighted by K_jk (the trace term).
double edgeStretches(const Matrix34d& xe, const EdgeLengthLiteralTet& t, double (&d)[6]) {
  double trace = 0.0;
  for (int e = 0; e < 6; ++e) {
    d[e] = (xe.col(kEdgeNodes[e][1]) - xe.col(kEdgeNodes[e][0])).squaredNorm() - t.restSq[e];
    trace += d[e] * t.K[e];
  }
  return trace;
}

}  // namespace

Matrix34d edgeLengthLiteralGradient(const Matrix34d& xe, const EdgeLengthLiteralTet& t) {
  double d[6];
  const double trace = edgeStretches(xe, t, d);
  const auto& A2 = t.areaSq;
  const auto& a = t.fibreGrad;
  Matrix34d G = Matrix34d::Zero();
  for (int p = 0; p < 4; ++p) {
    for (int j = 0; j < 4; ++j) {
      if (j == p) continue;
      int k, m;
      otherTwo(j, p, k, m);
      const double dJP = d[kEdgeOf[j][p]], dMK = d[kEdgeOf[m][k]];
      const double fib = t.c * (dJP * a[p] * a[j] + dMK * a[m] * a[k]);
      const double Kmkjp = edgeK(t, m, p) * edgeK(t, k, j) + edgeK(t, m, j) * edgeK(t, k, p) -
                           edgeK(t, m, k) * edgeK(t, j, p);
      const double coefJ = fib * a[p] * a[j] + t.muScale * (dJP * A2[p] * A2[j] + dMK * Kmkjp) +
                           t.lambdaMuScale * trace * edgeK(t, j, p);
      const double coefK =
          fib * a[p] * a[k] - t.muScale * (dJP * A2[p] * edgeK(t, j, k) + dMK * A2[k] * edgeK(t, m, p));
      const double coefM =
          fib * a[p] * a[m] - t.muScale * (dJP * A2[p] * edgeK(t, j, m) + dMK * A2[m] * edgeK(t, k, p));
      G.col(p) += coefJ * (xe.col(p) - xe.col(j)) + coefK * (xe.col(p) - xe.col(k)) +
                  coefM * (xe.col(p) - xe.col(m));
    }
  }
  return G;
}

Matrix34d edgeLengthEq30Gradient(const Matrix34d& xe, const EdgeLengthLiteralTet& t) {
  double d[6];
  const double trace = edgeStretches(xe, t, d);
  const auto& A2 = t.areaSq;
  const auto& a = t.fibreGrad;
  Matrix34d G;
  for (int p = 0; p < 4; ++p) {
    Eigen::Vector3d volumetric = Eigen::Vector3d::Zero();  // sum over j-p of Q_jQ_p K_jp
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (int j = 0; j < 4; ++j) {  // lines 2-3: the edges j-p; k, m the other two nodes
      if (j == p) continue;
      int k, m;
      otherTwo(j, p, k, m);
      const Eigen::Vector3d qj = xe.col(p) - xe.col(j), qk = xe.col(p) - xe.col(k),
                            qm = xe.col(p) - xe.col(m);
      const double dJP = d[kEdgeOf[j][p]];
      volumetric += edgeK(t, j, p) * qj;
      g += (t.muScale * A2[p] * dJP) * (A2[j] * qj - edgeK(t, j, k) * qk - edgeK(t, j, m) * qm);
      g += (t.c * a[p] * a[p] * a[j] * dJP) * (a[j] * qj + a[k] * qk + a[m] * qm);
    }
    g += (t.lambdaMuScale * trace) * volumetric;  // line 1
    for (int e = 0; e < 6; ++e) {  // lines 4-5: the edges j-k opposite p; m the fourth node
      const int j = kEdgeNodes[e][0], k = kEdgeNodes[e][1];
      if (j == p || k == p) continue;
      const int m = 6 - j - k - p;
      const Eigen::Vector3d qj = xe.col(p) - xe.col(j), qk = xe.col(p) - xe.col(k),
                            qm = xe.col(p) - xe.col(m);
      const double Kjkmp = edgeK(t, j, p) * edgeK(t, k, m) + edgeK(t, j, m) * edgeK(t, k, p) -
                           edgeK(t, j, k) * edgeK(t, m, p);  // Eq 21
      g += (t.muScale * d[e]) *
           (Kjkmp * qm - A2[j] * edgeK(t, k, p) * qj - A2[k] * edgeK(t, j, p) * qk);
      g += (t.c * a[p] * d[e] * a[j] * a[k]) * (a[m] * qm + a[j] * qj + a[k] * qk);
    }
    G.col(p) = g;
  }
  return G;
}

double edgeLengthLiteralDensity(const Matrix34d& xe, const EdgeLengthLiteralTet& t) {
  double d[6];
  double trace = 0.0;
  for (int e = 0; e < 6; ++e) {
    d[e] = (xe.col(kEdgeNodes[e][1]) - xe.col(kEdgeNodes[e][0])).squaredNorm() - t.restSq[e];
    trace += d[e] * t.K[e];
  }
  const auto& A2 = t.areaSq;
  const auto& a = t.fibreGrad;
  const double w = 0.5 * t.muScale;  // mu / (324 V^4)
  const double h = 0.5 * t.c;        // (dLambda/2 + dMu) / 2
  double W = 0.25 * t.lambdaMuScale * trace * trace;
  for (int e = 0; e < 6; ++e) {  // single edges
    const int j = kEdgeNodes[e][0], k = kEdgeNodes[e][1];
    W += 0.5 * d[e] * d[e] * (w * A2[j] * A2[k] + h * a[j] * a[j] * a[k] * a[k]);
  }
  for (int j = 0; j < 4; ++j) {  // the 12 pairs of edges sharing exactly node j
    for (int k = 0; k < 4; ++k) {
      for (int m = k + 1; m < 4; ++m) {
        if (k == j || m == j) continue;
        W -= d[kEdgeOf[j][k]] * d[kEdgeOf[j][m]] *
             (w * A2[j] * edgeK(t, k, m) - h * a[j] * a[j] * a[k] * a[m]);
      }
    }
  }
  for (int e = 0; e < 3; ++e) {  // the 3 pairs of opposite edges j-k, m-n
    const int j = kEdgeNodes[e][0], k = kEdgeNodes[e][1];
    const int f = 5 - e;
    const int m = kEdgeNodes[f][0], n = kEdgeNodes[f][1];
    const double KK = edgeK(t, j, n) * edgeK(t, k, m) + edgeK(t, j, m) * edgeK(t, k, n) -
                      edgeK(t, j, k) * edgeK(t, m, n);
    W += d[e] * d[f] * (w * KK + h * a[j] * a[k] * a[m] * a[n]);
  }
  return W;
}

EdgeLengthModel::EdgeLengthModel(const Mesh& mesh, const std::vector<Material>& materials,
                                 EdgeLengthPath path, bool psdProjection)
    : tets_(mesh.tets), stvk_(makeStvkTets(mesh, materials)), path_(path), psdProjection_(psdProjection) {
  if (path_ == EdgeLengthPath::kFast) return;
  literal_.resize(tets_.size());
  for (size_t e = 0; e < tets_.size(); ++e)
    literal_[e] = makeEdgeLengthLiteralTet(mesh.rest, tets_[e], stvk_[e].fibre,
                                           materials.at(mesh.material.at(e)));
}

double EdgeLengthModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& /*v*/,
                                 Eigen::VectorXd& f) const {
  if (path_ == EdgeLengthPath::kFast) return addStvkForces(x, tets_, stvk_, f);
  return accumulateTetForces(tets_, f, [&](int e, Matrix34d& fe) {
    const Matrix34d xe = gatherTet(x, tets_[e]);
    const EdgeLengthLiteralTet& t = literal_[e];
    if (path_ == EdgeLengthPath::kEq30) fe.noalias() = -t.volume * edgeLengthEq30Gradient(xe, t);
    else fe.noalias() = -t.volume * edgeLengthLiteralGradient(xe, t);
    return t.volume * edgeLengthLiteralDensity(xe, t);
  });
}

double EdgeLengthModel::energy(const Eigen::VectorXd& x) const {
  if (path_ == EdgeLengthPath::kFast) return stvkEnergy(x, tets_, stvk_);
  return sumOverTets(static_cast<int>(tets_.size()), [&](int e) {
    return literal_[e].volume * edgeLengthLiteralDensity(gatherTet(x, tets_[e]), literal_[e]);
  });
}

void EdgeLengthModel::addStiffness(const Eigen::VectorXd& x, double scale,
                                   const SparsePattern& pattern, SparseMatrix& K) const {
  addStvkStiffness(x, scale, tets_, stvk_, pattern, K, psdProjection_);
}

void EdgeLengthModel::addProjectedStiffness(const Eigen::VectorXd& x, double scale,
                                            const SparsePattern& pattern, SparseMatrix& K) const {
  addStvkStiffness(x, scale, tets_, stvk_, pattern, K, true);
}

}  // namespace tt
