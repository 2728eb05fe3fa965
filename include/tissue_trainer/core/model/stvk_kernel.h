#pragma once
// The St Venant-Kirchhoff tetrahedron with a fibre term (continuum definitions):
//   psi = lambda/2 tr(E)^2 + mu tr(E^2) + c (a0^T E a0)^2,   E = (F^T F - I)/2,
//   S = lambda tr(E) I + 2 mu E + 2 c (a0^T E a0) a0 a0^T,    P = F S,
//   tet energy V0 psi, physical nodal force f_p = -V0 P g_p.
// Shared by every tet model of Jeffrey, "A non-linear anisotropic Finite Element Method for
// surgical simulation" (their forces are this polynomial, or its linearisation at rest).
// Everything here is fixed-size: no allocation.
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/model/material.h"
#include "tissue_trainer/core/mesh/tet_geometry.h"
#include "tissue_trainer/core/model/tet_loops.h"
#include "tissue_trainer/core/solve/sparse_pattern.h"

namespace tt {

// Compact per-tet constants: rest volume, barycentric gradients, fibre, material.
struct StvkTet {
  double volume = 0.0;
  Matrix34d grad;          // column p is g_p
  Eigen::Vector3d fibre;   // unit a0
  double lambda = 0.0, mu = 0.0, c = 0.0;
};

inline StvkTet makeStvkTet(const Mesh& mesh, const std::vector<Material>& materials, int e) {
  const TetRest r = tetRest(mesh.rest, mesh.tets[e]);
  const ElasticConstants& m = materials.at(mesh.material.at(e)).elasticConstants();
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
// The same polynomial as stvkDensity/stvkSecondPiola, written for speed: E and S symmetric
// (6 entries), the fibre strain from b = F a0 (a0 . E a0 = (|b|^2 - 1)/2), -V0 folded into
// S, P g_p for p = 1..3 only (g_0 = -(g_1 + g_2 + g_3), so f_0 = -(f_1 + f_2 + f_3) and the
// forces sum to zero exactly).
inline double stvkTetForces(const Matrix34d& xe, const StvkTet& t, Matrix34d& fe) {
  const auto B = t.grad.rightCols<3>();  // column q is g_{q+1}; B^T = Dm^-1
  const Eigen::Matrix3d Ds = xe.rightCols<3>().colwise() - xe.col(0);
  Eigen::Matrix3d F;
  F.noalias() = Ds.lazyProduct(B.transpose());
  const double e00 = 0.5 * (F.col(0).squaredNorm() - 1.0);
  const double e11 = 0.5 * (F.col(1).squaredNorm() - 1.0);
  const double e22 = 0.5 * (F.col(2).squaredNorm() - 1.0);
  const double e01 = 0.5 * F.col(0).dot(F.col(1));
  const double e02 = 0.5 * F.col(0).dot(F.col(2));
  const double e12 = 0.5 * F.col(1).dot(F.col(2));
  const Eigen::Vector3d& a = t.fibre;
  const double fibreStrain = 0.5 * ((F * a).squaredNorm() - 1.0);
  const double tr = e00 + e11 + e22;
  const double V = t.volume;
  const double energy =
      V * (0.5 * t.lambda * tr * tr +
           t.mu * (e00 * e00 + e11 * e11 + e22 * e22 + 2.0 * (e01 * e01 + e02 * e02 + e12 * e12)) +
           t.c * fibreStrain * fibreStrain);
  const double m2 = -2.0 * V * t.mu, lt = -V * t.lambda * tr, cf = -2.0 * V * t.c * fibreStrain;
  Eigen::Matrix3d S;  // -V0 S
  S(0, 0) = m2 * e00 + lt + cf * a[0] * a[0];
  S(1, 1) = m2 * e11 + lt + cf * a[1] * a[1];
  S(2, 2) = m2 * e22 + lt + cf * a[2] * a[2];
  S(0, 1) = S(1, 0) = m2 * e01 + cf * a[0] * a[1];
  S(0, 2) = S(2, 0) = m2 * e02 + cf * a[0] * a[2];
  S(1, 2) = S(2, 1) = m2 * e12 + cf * a[1] * a[2];
  Eigen::Matrix3d P;
  P.noalias() = F.lazyProduct(S);
  fe.rightCols<3>().noalias() = P.lazyProduct(B);
  fe.col(0) = -(fe.col(1) + fe.col(2) + fe.col(3));
  return energy;
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

// S with its negative eigenvalues set to zero.
inline Eigen::Matrix3d positivePart(const Eigen::Matrix3d& S) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(S);
  if (eig.eigenvalues().minCoeff() >= 0.0) return S;
  const Eigen::Vector3d clamped = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
}

// K += scale * Ke of the tet at positions xe, straight into K's values through the tet's
// offsets in the pattern (the blocks of stvkTetStiffness, each computed once).
// Adds the rows of the local nodes in `rows` (all by default) of -scale dF/dx into K's values.
// psd: the energy Hessian made positive semi-definite for the system matrix. The Hessian is
//   dx^T H dx = V0 [tr(dF S dF^T) + lambda tr(dE)^2 + 2 mu dE:dE + 4 c (a0^T dE a0)^2],
//   dE = sym(F^T dF); with lambda, mu >= 0 only the geometric term (S with a negative
//   eigenvalue, under compression) and a negative fibre coefficient c can make it indefinite,
//   so S is replaced by its positive part there and c by max(c, 0): exactly PSD, and equal to
//   the Hessian wherever S is positive semi-definite and c >= 0.
inline void addStvkTetStiffness(const Matrix34d& xe, const StvkTet& t, double scale,
                                const std::array<int, 48>& offsets, double* values,
                                TetRows rows = kAllTetRows, bool psd = false) {
  const Eigen::Matrix3d F = tetDeformationGradient(xe, t.grad);
  const Eigen::Matrix3d S = psd ? positivePart(stvkSecondPiola(greenStrain(F), t))
                                : stvkSecondPiola(greenStrain(F), t);
  Matrix34d H;
  H.noalias() = F * t.grad;
  Matrix34d SG;
  SG.noalias() = S * t.grad;
  const Eigen::Matrix3d FFt = F * F.transpose();
  const Eigen::Vector3d b = F * t.fibre;
  const Eigen::Matrix3d bbt = b * b.transpose();
  const Eigen::Vector4d ag = t.grad.transpose() * t.fibre;
  const double v = -t.volume * scale;
  const double c = psd ? std::max(t.c, 0.0) : t.c;
  const double lambda = v * t.lambda, mu = v * t.mu, c2 = 2.0 * v * c;
  for (int p = 0; p < 4; ++p) {
    for (int q = p; q < 4; ++q) {
      Eigen::Matrix3d block = (mu * t.grad.col(p).dot(t.grad.col(q))) * FFt +
                              (c2 * ag[p] * ag[q]) * bbt;
      block.noalias() += (lambda * H.col(p)) * H.col(q).transpose();
      block.noalias() += (mu * H.col(q)) * H.col(p).transpose();
      block.diagonal().array() += v * t.grad.col(q).dot(SG.col(p));
      if (rows & (1u << p))
        for (int i = 0; i < 3; ++i) {
          double* row = values + offsets[(p * 4 + q) * 3 + i];
          for (int j = 0; j < 3; ++j) row[j] += block(i, j);
        }
      if (q == p || !(rows & (1u << q))) continue;
      for (int i = 0; i < 3; ++i) {
        double* row = values + offsets[(q * 4 + p) * 3 + i];
        for (int j = 0; j < 3; ++j) row[j] += block(j, i);
      }
    }
  }
}

// Whole-mesh loops shared by the models whose force is the StVK polynomial.
inline double addStvkForces(const Eigen::VectorXd& x, const std::vector<Tet>& tets,
                            const std::vector<StvkTet>& data, Eigen::VectorXd& f) {
  return accumulateTetForces(tets, f, [&](int e, Matrix34d& fe) {
    return stvkTetForces(gatherTet(x, tets[e]), data[e], fe);
  });
}

inline double stvkEnergy(const Eigen::VectorXd& x, const std::vector<Tet>& tets,
                         const std::vector<StvkTet>& data) {
  return sumOverTets(static_cast<int>(tets.size()),
                     [&](int e) { return stvkTetEnergy(gatherTet(x, tets[e]), data[e]); });
}

inline void addStvkStiffness(const Eigen::VectorXd& x, double scale, const std::vector<Tet>& tets,
                             const std::vector<StvkTet>& data, const SparsePattern& pattern,
                             SparseMatrix& K, bool psd = false) {
  double* values = K.valuePtr();
  forEachTetByRows(pattern, static_cast<int>(tets.size()), [&](int e, TetRows rows) {
    addStvkTetStiffness(gatherTet(x, tets[e]), data[e], scale, pattern.tetOffsets(e), values,
                        rows, psd);
  });
}

}  // namespace tt
