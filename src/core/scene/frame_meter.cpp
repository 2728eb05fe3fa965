#include "tissue_trainer/core/scene/frame_meter.h"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

#include "tissue_trainer/core/mesh/quality.h"

namespace tt {
namespace {

Eigen::Matrix3d edgeMatrix(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Tet& t) {
  Eigen::Matrix3d D;
  D << x.col(t[1]) - x.col(t[0]), x.col(t[2]) - x.col(t[0]), x.col(t[3]) - x.col(t[0]);
  return D;
}

}  // namespace

FrameMeter::FrameMeter(const System& system)
    : numNodes_(system.numNodes()), numHexes_(system.mesh.numHexes()) {
  const Mesh& mesh = system.mesh;
  tets_.reserve(mesh.tets.size());
  for (const Tet& t : mesh.tets) {
    const Eigen::Matrix3d Dm = edgeMatrix(mesh.rest, t);
    RestTet r;
    r.volume = Dm.determinant() / 6.0;
    r.edgesInverse = Dm.inverse();
    // As measureStrain: a tet flat at rest has no strain to measure.
    r.strained = std::abs(r.volume) > 0.0 && r.edgesInverse.allFinite();
    restVolume_ += r.volume;
    tets_.push_back(r);
  }
  for (const Hex& h : mesh.hexes) restVolume_ += hexVolume(mesh.rest, h);
  massPerAxis_ = Eigen::Map<const Eigen::Matrix3Xd>(system.mass.data(), 3, numNodes_).rowwise().sum();
}

FrameStatus FrameMeter::measure(const System& system, int frame, const StepReport& step,
                                double damageStrain) const {
  if (system.numNodes() != numNodes_ || system.mesh.numTets() != static_cast<int>(tets_.size()) ||
      system.mesh.numHexes() != numHexes_)
    throw std::invalid_argument("FrameMeter: built for " + std::to_string(numNodes_) + " nodes and " +
                                std::to_string(tets_.size()) + " tets, given a system of " +
                                std::to_string(system.numNodes()) + " nodes and " +
                                std::to_string(system.mesh.numTets()) + " tets");
  FrameStatus status;
  FrameLog& log = status.frame;
  StrainSummary& strain = status.strain;
  log.frame = frame;
  log.time = system.state.t;
  log.kineticEnergy = system.kineticEnergy(system.state.v);
  for (const auto& model : system.models)
    (model->isBodyLoad() ? log.loadEnergy : log.elasticEnergy) += model->energy(system.state.x);

  const Eigen::Map<const Eigen::Matrix3Xd> x(system.state.x.data(), 3, numNodes_);
  const Mesh& mesh = system.mesh;
  for (size_t e = 0; e < tets_.size(); ++e) {
    const RestTet& rest = tets_[e];
    const Eigen::Matrix3d Ds = edgeMatrix(x, mesh.tets[e]);
    log.volume += Ds.determinant() / 6.0;
    if (!rest.strained) continue;
    const Eigen::Matrix3d F = Ds * rest.edgesInverse;
    const double norm = (0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity())).norm();
    if (!std::isfinite(norm)) continue;
    if (norm > strain.maxStrain) strain.maxStrain = norm;
    if (norm > damageStrain) {
      strain.strainedVolume += std::abs(rest.volume);
      ++strain.strainedTets;
    }
  }
  for (const Hex& h : mesh.hexes) log.volume += hexVolume(x, h);
  log.volumeRatio = log.volume / restVolume_;
  if (numNodes_ > 0) log.maxDisplacement = (x - mesh.rest).colwise().norm().maxCoeff();
  const Eigen::Map<const Eigen::Matrix3Xd> m(system.mass.data(), 3, numNodes_);
  log.barycentre = m.cwiseProduct(x).rowwise().sum().cwiseQuotient(massPerAxis_);
  for (const auto& model : system.models)
    for (int k = 0; k < model->observableCount(); ++k)
      log.observables.push_back(model->observable(k, system.state.x));
  log.step = step;
  return status;
}

}  // namespace tt
