#pragma once
// The St Venant-Kirchhoff tetrahedron with a fibre term (ERRATA, "Continuum reference"):
//   psi = lambda/2 tr(E)^2 + mu tr(E^2) + c (a0^T E a0)^2,   E = (F^T F - I)/2,
//   S = lambda tr(E) I + 2 mu E + 2 c (a0^T E a0) a0 a0^T,    P = F S,
//   tet energy V0 psi, physical nodal force f_p = -V0 P g_p.
// Shared by every tet model of seed 000 (their forces are this polynomial, or its
// linearisation at rest). Everything here is fixed-size: no allocation.
#include <Eigen/Core>
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/model/material.h"
#include "tissue_trainer/core/model/tet_geometry.h"
#include "tissue_trainer/core/solve/sparse_pattern.h"

namespace tt {

using Matrix34d = Eigen::Matrix<double, 3, 4>;

// Compact per-tet constants: rest volume, barycentric gradients, fibre, material.
struct StvkTet {
  double volume = 0.0;
  Matrix34d grad;          // column p is g_p
  Eigen::Vector3d fibre;   // unit a0
  double lambda = 0.0, mu = 0.0, c = 0.0;
};

inline StvkTet makeStvkTet(const Mesh& mesh, const std::vector<Material>& materials, int e) {
  const TetRest r = tetRest(mesh.rest, mesh.tets[e]);
  const Material& m = materials.at(mesh.material.at(e));
  StvkTet t;
  t.volume = r.volume;
  t.grad = r.grad;
  t.fibre = mesh.fibreFrame.at(e).col(0).normalized();
  t.lambda = m.lambda;
  t.mu = m.mu;
  t.c = m.fibreCoefficient();
  return t;
}

inline std::vector<StvkTet> makeStvkTets(const Mesh& mesh, const std::vector<Material>& materials) {
  std::vector<StvkTet> tets(mesh.tets.size());
  for (int e = 0; e < mesh.numTets(); ++e) tets[e] = makeStvkTet(mesh, materials, e);
  return tets;
}

// The four node positions (or displacements) of tet t as columns.
inline Matrix34d gatherTet(const Eigen::VectorXd& x, const Tet& t) {
  Matrix34d xe;
  for (int p = 0; p < 4; ++p) xe.col(p) = x.segment<3>(3 * t[p]);
  return xe;
}

inline void scatterAddTet(const Matrix34d& fe, const Tet& t, Eigen::VectorXd& f) {
  for (int p = 0; p < 4; ++p) f.segment<3>(3 * t[p]) += fe.col(p);
}

// F = Ds Dm^-1 from the edge vectors x_p - x_0 (not sum_p x_p g_p^T): far from the origin the
// differences are exact, so a rigid translation costs no digits.
inline Eigen::Matrix3d tetDeformationGradient(const Matrix34d& xe, const Matrix34d& grad) {
  const Eigen::Matrix3d Ds = xe.rightCols<3>().colwise() - xe.col(0);
  return Ds * grad.rightCols<3>().transpose();
}

inline Eigen::Matrix3d greenStrain(const Eigen::Matrix3d& F) {
  return 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
}

inline double stvkDensity(const Eigen::Matrix3d& E, const StvkTet& t) {
  const double tr = E.trace();
  const double fibreStrain = t.fibre.dot(E * t.fibre);
  return 0.5 * t.lambda * tr * tr + t.mu * (E.array() * E.array()).sum() +
         t.c * fibreStrain * fibreStrain;
}

inline Eigen::Matrix3d stvkSecondPiola(const Eigen::Matrix3d& E, const StvkTet& t) {
  const double fibreStrain = t.fibre.dot(E * t.fibre);
  Eigen::Matrix3d S = 2.0 * t.mu * E;
  S.diagonal().array() += t.lambda * E.trace();
  S.noalias() += (2.0 * t.c * fibreStrain) * t.fibre * t.fibre.transpose();
  return S;
}

// Physical nodal forces of the tet at positions xe (columns) into fe; returns V0 psi.
inline double stvkTetForces(const Matrix34d& xe, const StvkTet& t, Matrix34d& fe) {
  const Eigen::Matrix3d F = tetDeformationGradient(xe, t.grad);
  const Eigen::Matrix3d E = greenStrain(F);
  const Eigen::Matrix3d S = stvkSecondPiola(E, t);
  fe.noalias() = (-t.volume) * (F * S) * t.grad;
  return t.volume * stvkDensity(E, t);
}

inline double stvkTetEnergy(const Matrix34d& xe, const StvkTet& t) {
  return t.volume * stvkDensity(greenStrain(tetDeformationGradient(xe, t.grad)), t);
}

// Ke = d f / d x (12 x 12, node-major: row 3p+i, column 3q+j). With h_q = F g_q, b = F a0:
//   d(P g_p)/dx_q = (g_q^T S g_p) I + lambda h_p h_q^T + mu (g_p.g_q) F F^T + mu h_q h_p^T
//                   + 2 c (a0.g_p)(a0.g_q) b b^T,
// and Ke_pq = -V0 times that.
inline void stvkTetStiffness(const Matrix34d& xe, const StvkTet& t, Matrix12d& Ke) {
  const Eigen::Matrix3d F = tetDeformationGradient(xe, t.grad);
  const Eigen::Matrix3d S = stvkSecondPiola(greenStrain(F), t);
  const Matrix34d H = F * t.grad;
  const Eigen::Matrix4d GSG = t.grad.transpose() * S * t.grad;
  const Eigen::Matrix4d GG = t.grad.transpose() * t.grad;
  const Eigen::Matrix3d FFt = F * F.transpose();
  const Eigen::Vector3d b = F * t.fibre;
  const Eigen::Matrix3d bbt = b * b.transpose();
  const Eigen::Vector4d ag = t.grad.transpose() * t.fibre;
  const double v = -t.volume;
  for (int p = 0; p < 4; ++p) {
    for (int q = p; q < 4; ++q) {
      Eigen::Matrix3d block = t.lambda * H.col(p) * H.col(q).transpose() +
                              t.mu * H.col(q) * H.col(p).transpose() +
                              (t.mu * GG(p, q)) * FFt + (2.0 * t.c * ag[p] * ag[q]) * bbt;
      block.diagonal().array() += GSG(q, p);
      Ke.block<3, 3>(3 * p, 3 * q) = v * block;
      if (q != p) Ke.block<3, 3>(3 * q, 3 * p) = v * block.transpose();
    }
  }
}

// Whole-mesh loops shared by the models whose force is the StVK polynomial.
inline double addStvkForces(const Eigen::VectorXd& x, const std::vector<Tet>& tets,
                            const std::vector<StvkTet>& data, Eigen::VectorXd& f) {
  double energy = 0.0;
  Matrix34d fe;
  for (size_t e = 0; e < tets.size(); ++e) {
    energy += stvkTetForces(gatherTet(x, tets[e]), data[e], fe);
    scatterAddTet(fe, tets[e], f);
  }
  return energy;
}

inline double stvkEnergy(const Eigen::VectorXd& x, const std::vector<Tet>& tets,
                         const std::vector<StvkTet>& data) {
  double energy = 0.0;
  for (size_t e = 0; e < tets.size(); ++e) energy += stvkTetEnergy(gatherTet(x, tets[e]), data[e]);
  return energy;
}

inline void addStvkStiffness(const Eigen::VectorXd& x, double scale, const std::vector<Tet>& tets,
                             const std::vector<StvkTet>& data, const SparsePattern& pattern,
                             SparseMatrix& K) {
  Matrix12d Ke;
  for (size_t e = 0; e < tets.size(); ++e) {
    stvkTetStiffness(gatherTet(x, tets[e]), data[e], Ke);
    Ke *= scale;
    pattern.addTetBlock(K, static_cast<int>(e), Ke);
  }
}

}  // namespace tt
