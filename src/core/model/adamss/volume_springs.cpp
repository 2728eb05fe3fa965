#include "tissue_trainer/core/model/adamss/volume_springs.h"

#include <stdexcept>
#include <string>

#include "tissue_trainer/core/element/element.h"
#include "tissue_trainer/core/model/tet_loops.h"

namespace tt {
namespace adamss {
namespace {

template <int N>
Eigen::Matrix<double, N, 1> restLengths(const Mesh& mesh, const std::array<int, N>& nodes,
                                        const char* kind, std::size_t e) {
  const NodeMatrix<N> X = gatherNodes<N>(mesh.rest, nodes);
  const Eigen::Matrix<double, N, 1> lengths =
      (X.colwise() - X.rowwise().mean()).colwise().norm().transpose();
  if (!(lengths.minCoeff() > 0.0))
    throw std::invalid_argument(std::string("adamss_volume_springs: ") + kind + " " +
                                std::to_string(e) + " has a node at its barycentre");
  return lengths;
}

// The forces of one element (columns) and its energy. `volumeTerm`: the tet's summed spring
// (Eq. 2.76) instead of one spring per node (Eq. 2.75).
template <int N>
double elementForces(const NodeMatrix<N>& x, const NodeMatrix<N>& v,
                     const Eigen::Matrix<double, N, 1>& rest, const VolumeSpringParameters& p,
                     bool volumeTerm, NodeMatrix<N>& fe) {
  const NodeMatrix<N> xi = x.colwise() - x.rowwise().mean();
  const NodeMatrix<N> theta = v.colwise() - v.rowwise().mean();
  const Eigen::Matrix<double, N, 1> lengths = xi.colwise().norm().transpose();
  const double total = lengths.sum() - rest.sum();
  double energy = 0.0;
  for (int i = 0; i < N; ++i) {
    const Eigen::Vector3d u = xi.col(i) / lengths[i];
    const double stretch = volumeTerm ? total : lengths[i] - rest[i];
    const double damping = volumeTerm ? 0.0 : p.damping * theta.col(i).dot(u);
    fe.col(i) = -(p.stiffness * stretch + damping) * u;
    if (!volumeTerm) energy += 0.5 * p.stiffness * stretch * stretch;
  }
  if (volumeTerm) energy = 0.5 * p.stiffness * total * total;
  if (p.gradient) fe.colwise() -= fe.rowwise().mean();
  return energy;
}

}  // namespace

VolumeSpringModel::VolumeSpringModel(const Mesh& mesh, const VolumeSpringParameters& parameters)
    : tets_(mesh.tets), hexes_(mesh.hexes), parameters_(parameters) {
  for (std::size_t e = 0; e < tets_.size(); ++e)
    tetRest_.push_back(restLengths<4>(mesh, tets_[e], "tet", e));
  for (std::size_t e = 0; e < hexes_.size(); ++e)
    hexRest_.push_back(restLengths<8>(mesh, hexes_[e], "hex", e));
}

double VolumeSpringModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                                   Eigen::VectorXd& f) const {
  const double tets = accumulateElementForces<4>(tets_, f, [&](int e, NodeMatrix<4>& fe) {
    return elementForces<4>(gatherNodes<4>(x, tets_[e]), gatherNodes<4>(v, tets_[e]),
                            tetRest_[e], parameters_, true, fe);
  });
  const double hexes = accumulateElementForces<8>(hexes_, f, [&](int e, NodeMatrix<8>& fe) {
    return elementForces<8>(gatherNodes<8>(x, hexes_[e]), gatherNodes<8>(v, hexes_[e]),
                            hexRest_[e], parameters_, false, fe);
  });
  return parameters_.gradient ? tets + hexes : 0.0;
}

double VolumeSpringModel::energy(const Eigen::VectorXd& x) const {
  if (!parameters_.gradient) return 0.0;
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(x.size());
  Eigen::VectorXd unused = Eigen::VectorXd::Zero(x.size());
  return addForce(x, still, unused);
}

}  // namespace adamss
}  // namespace tt
