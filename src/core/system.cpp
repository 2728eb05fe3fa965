#include "tissue_trainer/core/system.h"

#include <algorithm>
#include <cmath>

#include "tissue_trainer/core/mesh/quality.h"
#include "tissue_trainer/core/model/activated_force_model.h"

namespace tt {

namespace {

Eigen::Vector3d pathOffset(const PrescribedPath& p, double t) {
  if (p.times.empty()) return Eigen::Vector3d::Zero();
  if (t <= p.times.front()) return p.offsets.front();
  if (t >= p.times.back()) return p.offsets.back();
  const size_t k = std::upper_bound(p.times.begin(), p.times.end(), t) - p.times.begin();
  const double s = (t - p.times[k - 1]) / (p.times[k] - p.times[k - 1]);
  return (1.0 - s) * p.offsets[k - 1] + s * p.offsets[k];
}

Eigen::Vector3d pathVelocity(const PrescribedPath& p, double t) {
  if (p.times.size() < 2 || t < p.times.front() || t >= p.times.back())
    return Eigen::Vector3d::Zero();
  const size_t k = std::upper_bound(p.times.begin(), p.times.end(), t) - p.times.begin();
  return (p.offsets[k] - p.offsets[k - 1]) / (p.times[k] - p.times[k - 1]);
}

}  // namespace

Eigen::Vector3d PrescribedPath::offsetAt(double t) const {
  return pathOffset(*this, t) + velocity * std::max(t, 0.0);
}

Eigen::Vector3d PrescribedPath::velocityAt(double t) const {
  return pathVelocity(*this, t) + (t >= 0.0 ? velocity : Eigen::Vector3d::Zero());
}

System::System(Mesh m, std::vector<Material> mats)
    : mesh(std::move(m)), materials(std::move(mats)) {
  const int n = mesh.numNodes();
  mesh.fillDefaults();
  pattern = meshPattern(mesh);
  mass = Eigen::VectorXd::Zero(3 * n);
  for (int e = 0; e < mesh.numTets(); ++e) {
    const double quarter = 0.25 * materials.at(mesh.material[e]).density *
                           std::abs(tetVolume(mesh.rest, mesh.tets[e]));
    for (int a : mesh.tets[e]) mass.segment<3>(3 * a).array() += quarter;
  }
  // A hex mesh (without its tets) lumps an eighth of each hex's mass on each of its nodes.
  for (int e = 0; e < mesh.numHexes(); ++e) {
    const double eighth = 0.125 * materials.at(mesh.hexMaterial[e]).density *
                          std::abs(hexVolume(mesh.rest, mesh.hexes[e]));
    for (int a : mesh.hexes[e]) mass.segment<3>(3 * a).array() += eighth;
  }
  damping = Eigen::VectorXd::Zero(3 * n);
  externalForce = Eigen::VectorXd::Zero(3 * n);
  state.x = Eigen::Map<const Eigen::VectorXd>(mesh.rest.data(), 3 * n);
  state.v = Eigen::VectorXd::Zero(3 * n);
  updateConstraints();
}

void System::addCouplingsToPattern() {
  std::vector<std::array<int, 2>> pairs;
  for (const auto& model : models)
    for (const auto& pair : model->couplings()) pairs.push_back(pair);
  pattern = meshPattern(mesh, std::move(pairs));
}

double System::computeForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                            Eigen::VectorXd& f) const {
  f = externalForce - damping.cwiseProduct(v);
  double energy = 0.0;
  for (const auto& model : models) energy += model->addForce(x, v, f);
  return energy;
}

void System::beginStep(double t) {
  for (auto& model : models)
    if (model->needsStepUpdates()) model->beginStep(t, state.x, state.v);
}

double System::potentialEnergy(const Eigen::VectorXd& x) const {
  double energy = 0.0;
  for (const auto& model : models) energy += model->energy(x);
  return energy;
}

double System::kineticEnergy(const Eigen::VectorXd& v) const {
  return 0.5 * v.dot(mass.cwiseProduct(v));
}

bool System::hasStiffness() const {
  return std::all_of(models.begin(), models.end(),
                     [](const auto& m) { return m->hasStiffness(); });
}

void System::assembleStiffness(const Eigen::VectorXd& x, SparseMatrix& K, double scale,
                               bool projected) const {
  if (K.nonZeros() != pattern.nonZeros()) K = pattern.zeroMatrix();  // first call, new couplings
  std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
  for (const auto& model : models) {
    if (!model->hasStiffness()) continue;
    if (projected)
      model->addProjectedStiffness(x, scale, pattern, K);
    else
      model->addStiffness(x, scale, pattern, K);
  }
}

bool System::hasProjectedStiffness() const {
  return std::any_of(models.begin(), models.end(), [](const auto& m) { return m->hasProjectedStiffness(); });
}

bool System::hasVelocityJacobian() const {
  return std::any_of(models.begin(), models.end(),
                     [](const auto& m) { return m->hasVelocityJacobian(); });
}

void System::assembleVelocityJacobian(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                                      SparseMatrix& C) const {
  if (C.nonZeros() == 0) C = pattern.zeroMatrix();
  std::fill(C.valuePtr(), C.valuePtr() + C.nonZeros(), 0.0);
  for (const auto& model : models)
    if (model->hasVelocityJacobian()) model->addVelocityJacobian(x, v, 1.0, pattern, C);
}

void System::prescribe(double t, Eigen::VectorXd& x, Eigen::VectorXd& v) const {
  for (int n = 0; n < numNodes(); ++n) {
    const std::uint8_t tags = mesh.nodeTags[n];
    for (int axis = 0; axis < 3; ++axis)
      if (tags & (1u << axis)) {
        x[3 * n + axis] = mesh.rest(axis, n);
        v[3 * n + axis] = 0.0;
      }
  }
  for (const ControlledSet& set : controlled) {
    const Eigen::Vector3d offset = set.path.offsetAt(t);
    const Eigen::Vector3d velocity = set.path.velocityAt(t);
    for (int n : set.nodes)
      for (int axis = 0; axis < 3; ++axis)
        if (set.axes & (1u << axis)) {
          x[3 * n + axis] = mesh.rest(axis, n) + offset[axis];
          v[3 * n + axis] = velocity[axis];
        }
  }
}

void System::zeroConstrained(Eigen::VectorXd& r) const {
  for (int dof : constrainedDofs) r[dof] = 0.0;
}

void System::constrainMatrix(SparseMatrix& A) const {
  for (int row = 0; row < A.outerSize(); ++row)
    for (SparseMatrix::InnerIterator it(A, row); it; ++it)
      if (isConstrained[row] || isConstrained[it.col()])
        it.valueRef() = (row == it.col()) ? 1.0 : 0.0;
}

void System::updateConstraints() {
  const int n = numNodes();
  mesh.nodeTags.resize(n, 0);
  isConstrained.assign(3 * n, 0);
  for (int node = 0; node < n; ++node)
    for (int axis = 0; axis < 3; ++axis)
      if (mesh.nodeTags[node] & (1u << axis)) isConstrained[3 * node + axis] = 1;
  for (const ControlledSet& set : controlled)
    for (int node : set.nodes) {
      mesh.nodeTags[node] |= kControlled;
      for (int axis = 0; axis < 3; ++axis)
        if (set.axes & (1u << axis)) isConstrained[3 * node + axis] = 1;
    }
  constrainedDofs.clear();
  for (int dof = 0; dof < 3 * n; ++dof)
    if (isConstrained[dof]) constrainedDofs.push_back(dof);
}

ActivationRef System::findActivation(const std::string& name) const {
  for (const auto& model : models)
    if (auto* activated = dynamic_cast<ActivatedForceModel*>(model.get()))
      for (int i = 0; i < activated->activationCount(); ++i)
        if (activated->activationName(i) == name) return {activated, i};
  return {};
}

}  // namespace tt
