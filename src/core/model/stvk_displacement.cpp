#include "tissue_trainer/core/model/stvk_displacement.h"

namespace tt {

bool parseAlphaSign(const std::string& name, AlphaSign& sign) {
  if (name == "correct") sign = AlphaSign::kCorrect;
  else if (name == "paper_literal") sign = AlphaSign::kPaperLiteral;
  else return false;
  return true;
}

double picinbonoTetGradient(const Matrix34d& U, const StvkTet& t, double alphaSign, Matrix34d& G) {
  const Matrix34d alpha = alphaSign * t.grad;
  const Eigen::Vector3d& a0 = t.fibre;
  const Eigen::Matrix4d A = alpha.transpose() * alpha;   // alpha_j . alpha_k
  const Eigen::Vector4d a = alpha.transpose() * a0;      // a0 . alpha_j
  const Eigen::Matrix4d UU = U.transpose() * U;          // U_j . U_k
  const Eigen::Matrix4d Ua = U.transpose() * alpha;      // U_j . alpha_k
  const Eigen::Vector4d Ua0 = U.transpose() * a0;        // U_j . a0
  const double lambda = t.lambda, mu = t.mu, c = t.c;

  Matrix34d F2 = Matrix34d::Zero(), F3 = Matrix34d::Zero(), F4 = Matrix34d::Zero();
  for (int p = 0; p < 4; ++p) {
    for (int j = 0; j < 4; ++j) {
      // 2 B_pj U_j, Eq 16.
      F2.col(p) += lambda * Ua(j, j) * alpha.col(p) + mu * Ua(j, p) * alpha.col(j) +
                   mu * A(p, j) * U.col(j) + (2.0 * c * a[p] * a[j] * Ua0[j]) * a0;
      for (int k = 0; k < 4; ++k) {
        // 2 U_k (U_j . C_jkp) + (U_j . U_k) C_pjk, Eq 17.
        const double UjCjkp = 0.5 * lambda * Ua(j, j) * A(k, p) +
                              0.5 * mu * (Ua(j, p) * A(j, k) + Ua(j, k) * A(j, p)) +
                              c * a[j] * a[k] * a[p] * Ua0[j];
        F3.col(p) += 2.0 * UjCjkp * U.col(k) +
                     UU(j, k) * (0.5 * lambda * A(j, k) * alpha.col(p) +
                                 0.5 * mu * (A(p, j) * alpha.col(k) + A(p, k) * alpha.col(j)) +
                                 c * a[p] * a[j] * a[k] * a0);
        for (int l = 0; l < 4; ++l) {
          // 4 D_jklp U_l (U_k . U_j), Eq 18.
          const double D = 0.125 * lambda * A(j, k) * A(l, p) + 0.25 * mu * A(j, p) * A(k, l) +
                           0.25 * c * a[j] * a[k] * a[l] * a[p];
          F4.col(p) += (4.0 * D * UU(k, j)) * U.col(l);
        }
      }
    }
  }
  G = F2 + F3 + F4;
  return (U.array() * (F2 / 2.0 + F3 / 3.0 + F4 / 4.0).array()).sum();
}

StvkDisplacementModel::StvkDisplacementModel(const Mesh& mesh,
                                             const std::vector<Material>& materials,
                                             AlphaSign sign)
    : tets_(mesh.tets),
      stvk_(makeStvkTets(mesh, materials)),
      rest_(Eigen::Map<const Eigen::VectorXd>(mesh.rest.data(), 3 * mesh.numNodes())),
      sign_(sign) {}

double StvkDisplacementModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& /*v*/,
                                       Eigen::VectorXd& f) const {
  const double sign = signValue();
  return accumulateTetForces(tets_, f, [&](int e, Matrix34d& fe) {
    const Matrix34d U = gatherTet(x, tets_[e]) - gatherTet(rest_, tets_[e]);
    const double energy = stvk_[e].volume * picinbonoTetGradient(U, stvk_[e], sign, fe);
    fe *= -stvk_[e].volume;
    return energy;
  });
}

double StvkDisplacementModel::energy(const Eigen::VectorXd& x) const {
  const double sign = signValue();
  return sumOverTets(static_cast<int>(tets_.size()), [&](int e) {
    Matrix34d G;
    const Matrix34d U = gatherTet(x, tets_[e]) - gatherTet(rest_, tets_[e]);
    return stvk_[e].volume * picinbonoTetGradient(U, stvk_[e], sign, G);
  });
}

// With the correct sign the force is the StVK force, so is its Jacobian. With the printed sign
// f(x) = -f_StVK(2 rest - x), hence df/dx = K_StVK(2 rest - x).
void StvkDisplacementModel::addStiffness(const Eigen::VectorXd& x, double scale,
                                         const SparsePattern& pattern, SparseMatrix& K) const {
  double* values = K.valuePtr();
  forEachTetByRows(pattern, static_cast<int>(tets_.size()), [&](int e, TetRows rows) {
    const Matrix34d xe = gatherTet(x, tets_[e]);
    const Matrix34d at = sign_ == AlphaSign::kCorrect ? xe : 2.0 * gatherTet(rest_, tets_[e]) - xe;
    addStvkTetStiffness(at, stvk_[e], scale, pattern.tetOffsets(e), values, rows);
  });
}

}  // namespace tt
