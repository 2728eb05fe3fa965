#include "tissue_trainer/core/model/tensor_mass.h"

namespace tt {
namespace {

constexpr int kBlockOf[4][4] = {{0, 1, 2, 3}, {1, 4, 5, 6}, {2, 5, 7, 8}, {3, 6, 8, 9}};

}  // namespace

Eigen::Matrix3d tensorMassB(const StvkTet& t, int j, int k) {
  const Eigen::Vector3d aj = t.grad.col(j), ak = t.grad.col(k);
  Eigen::Matrix3d B = 0.5 * t.lambda * aj * ak.transpose() + 0.5 * t.mu * ak * aj.transpose();
  B.diagonal().array() += 0.5 * t.mu * aj.dot(ak);
  B += (t.c * t.fibre.dot(aj) * t.fibre.dot(ak)) * t.fibre * t.fibre.transpose();
  return B;
}

TensorMassModel::TensorMassModel(const Mesh& mesh, const std::vector<Material>& materials)
    : tets_(mesh.tets),
      blocks_(mesh.tets.size()),
      rest_(Eigen::Map<const Eigen::VectorXd>(mesh.rest.data(), 3 * mesh.numNodes())) {
  for (int e = 0; e < mesh.numTets(); ++e) {
    const StvkTet t = makeStvkTet(mesh, materials, e);
    for (int j = 0; j < 4; ++j)
      for (int k = j; k < 4; ++k) blocks_[e][kBlockOf[j][k]] = -2.0 * t.volume * tensorMassB(t, j, k);
  }
}

double TensorMassModel::tetForces(const Blocks& blocks, const Matrix34d& U, Matrix34d& fe) const {
  fe.setZero();
  for (int p = 0; p < 4; ++p) {
    fe.col(p).noalias() += blocks[kBlockOf[p][p]] * U.col(p);
    for (int q = p + 1; q < 4; ++q) {
      const Eigen::Matrix3d& Kpq = blocks[kBlockOf[p][q]];
      fe.col(p).noalias() += Kpq * U.col(q);
      fe.col(q).noalias() += Kpq.transpose() * U.col(p);
    }
  }
  return -0.5 * (U.array() * fe.array()).sum();
}

double TensorMassModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& /*v*/,
                                 Eigen::VectorXd& f) const {
  return accumulateTetForces(tets_, f, [&](int e, Matrix34d& fe) {
    return tetForces(blocks_[e], gatherTet(x, tets_[e]) - gatherTet(rest_, tets_[e]), fe);
  });
}

double TensorMassModel::energy(const Eigen::VectorXd& x) const {
  return sumOverTets(static_cast<int>(tets_.size()), [&](int e) {
    Matrix34d fe;
    return tetForces(blocks_[e], gatherTet(x, tets_[e]) - gatherTet(rest_, tets_[e]), fe);
  });
}

void TensorMassModel::addStiffness(const Eigen::VectorXd& /*x*/, double scale,
                                   const SparsePattern& pattern, SparseMatrix& K) const {
  double* values = K.valuePtr();
  forEachTetByRows(pattern, static_cast<int>(tets_.size()), [&](int e, TetRows rows) {
    const std::array<int, 48>& offsets = pattern.tetOffsets(e);
    for (int p = 0; p < 4; ++p) {
      if (!(rows & (1u << p))) continue;
      for (int q = 0; q < 4; ++q) {
        const Eigen::Matrix3d& block = blocks_[e][kBlockOf[p][q]];  // K_qp = K_pq^T
        for (int i = 0; i < 3; ++i) {
          double* row = values + offsets[(p * 4 + q) * 3 + i];
          for (int j = 0; j < 3; ++j) row[j] += scale * (p <= q ? block(i, j) : block(j, i));
        }
      }
    }
  });
}

}  // namespace tt
