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
  double energy = 0.0;
  Matrix34d fe;
  for (size_t e = 0; e < tets_.size(); ++e) {
    energy += tetForces(blocks_[e], gatherTet(x, tets_[e]) - gatherTet(rest_, tets_[e]), fe);
    scatterAddTet(fe, tets_[e], f);
  }
  return energy;
}

double TensorMassModel::energy(const Eigen::VectorXd& x) const {
  double energy = 0.0;
  Matrix34d fe;
  for (size_t e = 0; e < tets_.size(); ++e)
    energy += tetForces(blocks_[e], gatherTet(x, tets_[e]) - gatherTet(rest_, tets_[e]), fe);
  return energy;
}

void TensorMassModel::addStiffness(const Eigen::VectorXd& /*x*/, double scale,
                                   const SparsePattern& pattern, SparseMatrix& K) const {
  Matrix12d Ke;
  for (size_t e = 0; e < tets_.size(); ++e) {
    for (int p = 0; p < 4; ++p)
      for (int q = p; q < 4; ++q) {
        Ke.block<3, 3>(3 * p, 3 * q) = scale * blocks_[e][kBlockOf[p][q]];
        if (q != p) Ke.block<3, 3>(3 * q, 3 * p) = scale * blocks_[e][kBlockOf[p][q]].transpose();
      }
    pattern.addTetBlock(K, static_cast<int>(e), Ke);
  }
}

}  // namespace tt
