#include "tissue_trainer/core/model/adamss/lms_volume_springs.h"

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>
#include <string>

#include "tissue_trainer/core/model/tet_loops.h"

namespace tt {
namespace adamss {
namespace {

// sum_j |x_j - x_b| of a tet.
double lengthSum(const Matrix34d& x) {
  return (x.colwise() - x.rowwise().mean()).colwise().norm().sum();
}

double signedVolume(const Matrix34d& x) {
  Eigen::Matrix3d D;
  D << x.col(1) - x.col(0), x.col(2) - x.col(0), x.col(3) - x.col(0);
  return D.determinant() / 6.0;
}

}  // namespace

LmsVolumeSpringModel::LmsVolumeSpringModel(const Mesh& mesh,
                                           const LmsVolumeSpringParameters& parameters)
    : tets_(mesh.tets), parameters_(parameters) {
  if (!mesh.hexes.empty())
    throw std::invalid_argument("adamss_lms_volume_springs: tetrahedra only, and the mesh has " +
                                std::to_string(mesh.hexes.size()) + " hexahedra");
  const Eigen::VectorXd rest = Eigen::Map<const Eigen::VectorXd>(mesh.rest.data(), mesh.rest.size());
  for (std::size_t e = 0; e < tets_.size(); ++e) {
    const Matrix34d x = gatherTet(rest, tets_[e]);
    const Eigen::Vector4d lengths = (x.colwise() - x.rowwise().mean()).colwise().norm().transpose();
    if (!(lengths.minCoeff() > 0.0))
      throw std::invalid_argument("adamss_lms_volume_springs: tet " + std::to_string(e) +
                                  " has a node at its barycentre");
    restLengthSum_.push_back(lengths.sum());
    restVolume_.push_back(signedVolume(x));
  }
  stiffness_.assign(tets_.size(), parameters_.stiffness);
  history_.resize(kHistory);
  for (Checkpoint& c : history_) c.stiffness.resize(tets_.size());
}

void LmsVolumeSpringModel::beginStep(double t, const Eigen::VectorXd& x,
                                     const Eigen::VectorXd& /*v*/) {
  // A start seen before: undo its update and forget the later ones.
  int seen = kept_ - 1;
  while (seen >= 0 && checkpoint(seen).t != t) --seen;
  if (seen >= 0) {
    std::copy(checkpoint(seen).stiffness.begin(), checkpoint(seen).stiffness.end(),
              stiffness_.begin());
    kept_ = seen + 1;
  } else {
    if (kept_ == kHistory) {
      oldest_ = (oldest_ + 1) % kHistory;
      --kept_;
    }
    Checkpoint& c = checkpoint(kept_++);
    c.t = t;
    std::copy(stiffness_.begin(), stiffness_.end(), c.stiffness.begin());
  }
  for (std::size_t e = 0; e < tets_.size(); ++e) {
    const Matrix34d xe = gatherTet(x, tets_[e]);
    const double volumeError = signedVolume(xe) - restVolume_[e];  // Eq. 2.79
    const double lengths = lengthSum(xe);
    const double input = parameters_.printedUpdate ? lengths : lengths - restLengthSum_[e];
    stiffness_[e] = std::max(0.0, stiffness_[e] + parameters_.rate * volumeError * input);
  }
}

double LmsVolumeSpringModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& /*v*/,
                                      Eigen::VectorXd& f) const {
  const double energy = accumulateElementForces<4>(tets_, f, [&](int e, Matrix34d& fe) {
    const Matrix34d xe = gatherTet(x, tets_[e]);
    const Matrix34d xi = xe.colwise() - xe.rowwise().mean();
    const Eigen::RowVector4d lengths = xi.colwise().norm();
    const double strain = lengths.sum() - restLengthSum_[e];
    for (int i = 0; i < 4; ++i) fe.col(i) = (-stiffness_[e] * strain / lengths[i]) * xi.col(i);
    if (parameters_.gradient) fe.colwise() -= fe.rowwise().mean();
    return 0.5 * stiffness_[e] * strain * strain;
  });
  return parameters_.gradient ? energy : 0.0;
}

double LmsVolumeSpringModel::energy(const Eigen::VectorXd& x) const {
  if (!parameters_.gradient) return 0.0;
  double energy = 0.0;  // the sum addForce returns, without a force vector to fill
  for (std::size_t e = 0; e < tets_.size(); ++e) {
    const double strain = lengthSum(gatherTet(x, tets_[e])) - restLengthSum_[e];
    energy += 0.5 * stiffness_[e] * strain * strain;
  }
  return energy;
}

}  // namespace adamss
}  // namespace tt
